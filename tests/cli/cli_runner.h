// Runs the built rayaccel binary (testing::cli_path(), tests/test_paths.h) or another program from a test and captures its exit code,
// stdout and stderr; plus small file helpers the end-to-end tests share.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace rayaccel::testing {

/// A scene that builds in milliseconds, for the tests of what the CLI does around the tracing.
inline constexpr const char* kSphereScene = "builtin:sphere:level=1";

struct CommandResult {
  int exit_code = -1;  ///< the program's exit status; -1 when it did not exit normally (crash)
  std::string out;
  std::string err;
};

/// Runs program with args (each shell-quoted), waiting for it to finish.
CommandResult run_program(const std::string& program, const std::vector<std::string>& args);
/// Runs the rayaccel command-line tool.
CommandResult run_cli(const std::vector<std::string>& args);
/// Runs the rayaccel command-line tool under timeout(1): killed after `seconds` (exit code 124 then), so a hang
/// fails the test instead of stalling CI.
CommandResult run_cli_bounded(std::vector<std::string> args, int seconds = 60);

/// A fresh empty directory under the test temp dir, named after the running test.
std::filesystem::path fresh_directory(const std::string& tag);
std::string read_file(const std::filesystem::path& path);
/// Writes 64 rays along +z from z = -5 (a row of origins at y = 0) to dir/few.rays and returns its path.
std::filesystem::path some_rays(const std::filesystem::path& dir);
/// The last line of `out` that is not empty (the one-line JSON summary the CLI prints last).
std::string last_nonempty_line(const std::string& out);

}  // namespace rayaccel::testing
