// rayaccel command-line tool: parses the command line and dispatches to one file per subcommand. Exit codes: 0 ok,
// 1 runtime failure (unreadable file, mismatching structure), 2 usage error (bad option or value).
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "cli_common.h"
#include "commands.h"
#include "rayaccel/version.h"
#ifdef RAYACCEL_HAVE_EMBREE
#include "rayaccel/compare/embree_accelerator.h"
#endif

int main(int argc, char** argv) {
  using namespace rayaccel::cli;
#ifdef RAYACCEL_HAVE_EMBREE
  rayaccel::enable_embree_comparison();  // "embree" for --compare and --accel, before anything reads the registry
#endif
  CLI::App app{"rayaccel: ray-tracing acceleration structures behind one API, traced, rendered and benchmarked"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("rayaccel ") + RAYACCEL_VERSION_STRING);
  const std::vector<Command> commands = {add_list_command(app), add_info_command(app), add_trace_command(app),
                                         add_render_command(app), add_bench_command(app),
                                         add_query_command(app)};
  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    std::string names;
    for (const auto& command : commands) {
      known = known || command.app->get_name() == argv[1];
      names += (names.empty() ? "" : ", ") + command.app->get_name();
    }
    if (!known) {
      std::cerr << "rayaccel: error: unknown command '" << argv[1] << "' (known: " << names << ")\n";
      return kExitUsage;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "rayaccel: error: " << e.what() << "\n";
    std::cerr << "Run 'rayaccel --help' (or 'rayaccel COMMAND --help') for usage.\n";
    return kExitUsage;
  }
  for (const auto& command : commands) {
    if (!command.app->parsed()) continue;
    try {
      return command.run();
    } catch (const UsageError& e) {
      std::cerr << "rayaccel " << command.app->get_name() << ": error: " << e.what() << "\n";
      return kExitUsage;
    } catch (const std::exception& e) {
      std::cerr << "rayaccel " << command.app->get_name() << ": error: " << e.what() << "\n";
      return kExitRuntime;
    }
  }
  return kExitUsage;
}
