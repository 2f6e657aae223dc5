// The subcommands of the rayaccel tool, one file each. Each add_*_command() declares its options on `root` and
// returns the action main() runs when that subcommand was given.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace rayaccel::cli {

struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;  ///< returns the exit code; throws UsageError or Error on bad input
};

Command add_list_command(CLI::App& root);
Command add_info_command(CLI::App& root);
Command add_trace_command(CLI::App& root);
Command add_render_command(CLI::App& root);
Command add_bench_command(CLI::App& root);
Command add_query_command(CLI::App& root);

}  // namespace rayaccel::cli
