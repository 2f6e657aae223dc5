// Test helper: the message of the rayaccel::Error a call throws, for tests that check errors name their culprit.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "rayaccel/core/error.h"

namespace rayaccel::testing {

/// The message of the Error `f` throws; fails the test if it throws nothing.
template <class F>
std::string error_message(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected rayaccel::Error";
  return {};
}

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace rayaccel::testing
