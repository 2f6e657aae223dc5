// Unit tests of whole-or-nothing output files (core/output_file.h): replacement, no leftovers, a failed write (a
// file-size limit stands in for a full disk; /dev/full for a full device) that leaves the previous file intact and
// says so, and the output path checks made before any work.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "../scene/temp_dir.h"
#include "rayaccel/core/error.h"
#include "rayaccel/core/output_file.h"

namespace rayaccel {
namespace {

using testing::TempDir;

std::string contents(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::size_t entries(const std::filesystem::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++n;
  return n;
}

void expect_error(const std::function<void()>& f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    for (const auto& part : parts) EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(OutputFile, ReplacesTheFileAndLeavesNothingElse) {
  TempDir dir;
  const auto file = dir.path() / "out.txt";
  write_file_atomically(file, std::string_view("first"), "text");
  EXPECT_EQ(contents(file), "first");
  write_file_atomically(file, std::string_view("second, longer"), "text");
  EXPECT_EQ(contents(file), "second, longer");
  EXPECT_EQ(entries(dir.path()), 1u) << "no temporary file is left behind";
}

TEST(OutputFile, FailedWriteKeepsThePreviousFileAndSaysSo) {
  TempDir dir;
  const auto file = dir.path() / "keep.bin";
  write_file_atomically(file, std::string_view("previous contents"), "test file");
  // A file-size limit makes write() fail part-way (EFBIG), as a full disk would (ENOSPC).
  ::signal(SIGXFSZ, SIG_IGN);
  rlimit old{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  rlimit small = old;
  small.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  const std::string big(100000, 'x');
  bool failed = false;
  try {
    write_file_atomically(file, std::string_view(big), "test file");
  } catch (const Error& e) {
    failed = true;
    EXPECT_NE(std::string(e.what()).find("keep.bin"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("unchanged"), std::string::npos) << e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &old);
  EXPECT_TRUE(failed) << "a write past the size limit must fail";
  EXPECT_EQ(contents(file), "previous contents");
  EXPECT_EQ(entries(dir.path()), 1u) << "the temporary file is removed";
}

TEST(OutputFile, FullDeviceIsAnError) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  expect_error([] { write_file_atomically("/dev/full", std::string_view("data"), "test file"); },
               {"/dev/full", "No space left on device"});
}

TEST(OutputFile, PathsAreCheckedBeforeWork) {
  TempDir dir;
  expect_error([&] { check_output_path(dir.path() / "missing" / "x.png", "PNG"); }, {"x.png", "does not exist"});
  expect_error([&] { check_output_path(dir.path(), "PNG"); }, {"is a directory"});
  expect_error([&] { check_output_path("", "PNG"); }, {"empty"});
  check_output_path(dir.path() / "fine.png", "PNG");
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "fine.png")) << "checking creates nothing";
  const auto file = dir.write("a_file", "x");
  expect_error([&] { check_output_directory(file, "images"); }, {"a_file", "not a directory"});
  check_output_directory(dir.path() / "new" / "images", "images");
  EXPECT_TRUE(std::filesystem::is_directory(dir.path() / "new" / "images"));
}

}  // namespace
}  // namespace rayaccel
