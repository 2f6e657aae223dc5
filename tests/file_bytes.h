// Test helpers for file formats: a file's bytes read and written whole (to truncate, corrupt or forge a saved file),
// and the check that loading it fails with an Error naming the file and the fault.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "rayaccel/core/error.h"

namespace rayaccel::testing {

inline std::vector<char> read_all(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void write_all(const std::filesystem::path& p, const std::vector<char>& bytes) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// Runs f and expects an Error whose message names `file` and contains `fault`.
template <class F>
void expect_error(F f, const std::string& file, const std::string& fault) {
  try {
    f();
    ADD_FAILURE() << "no error for " << fault;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(file), std::string::npos) << message;
    EXPECT_NE(message.find(fault), std::string::npos) << message;
  }
}

}  // namespace rayaccel::testing
