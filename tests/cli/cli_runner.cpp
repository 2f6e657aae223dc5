// Process runner for the end-to-end tests (see cli_runner.h).
#include "cli_runner.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <atomic>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "rayaccel/scene/ray_io.h"
#include "../test_paths.h"

namespace rayaccel::testing {

namespace {

std::string shell_quote(const std::string& arg) {
  std::string out = "'";
  for (char c : arg) {
    if (c == '\'') {
      out.append("'\\''");
    } else {
      out.push_back(c);
    }
  }
  out.push_back('\'');
  return out;
}

}  // namespace

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

CommandResult run_cli_bounded(std::vector<std::string> args, int seconds) {
  args.insert(args.begin(), {std::to_string(seconds), cli_path()});
  return run_program("timeout", args);
}

std::filesystem::path some_rays(const std::filesystem::path& dir) {
  std::vector<Ray> rays(64);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    rays[i].origin = {0.01f * float(i), 0.0f, -5.0f};
    rays[i].direction = {0.0f, 0.0f, 1.0f};
  }
  const auto file = dir / "few.rays";
  write_rays(file, rays);
  return file;
}

std::filesystem::path fresh_directory(const std::string& tag) {
  static std::atomic<int> counter{0};
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string name = std::string(info ? info->test_suite_name() : "test") + "_" + (info ? info->name() : "") +
                           "_" + tag + "_" + std::to_string(counter++);
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "rayaccel_cli" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

CommandResult run_program(const std::string& program, const std::vector<std::string>& args) {
  const std::filesystem::path dir = fresh_directory("run");
  std::string command = shell_quote(program);
  for (const auto& arg : args) command.append(" ").append(shell_quote(arg));
  command.append(" >").append(shell_quote((dir / "out").string()));
  command.append(" 2>").append(shell_quote((dir / "err").string()));
  const int status = std::system(command.c_str());
  CommandResult result;
  result.exit_code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = read_file(dir / "out");
  result.err = read_file(dir / "err");
  return result;
}

CommandResult run_cli(const std::vector<std::string>& args) { return run_program(cli_path(), args); }

std::string last_nonempty_line(const std::string& out) {
  std::istringstream lines(out);
  std::string line, last;
  while (std::getline(lines, line)) {
    if (!line.empty()) last = line;
  }
  return last;
}

}  // namespace rayaccel::testing
