// `rayaccel list`: every registered structure with its description and options; `--names` prints only the specs
// of accelerator_variant_names(), one per line, for scripts.
#include <fmt/core.h>

#include <algorithm>
#include <memory>

#include "commands.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/scene/builtin_scenes.h"

namespace rayaccel::cli {

namespace {

std::string joined(const std::vector<std::string>& items, const char* separator) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : separator) + item;
  return out;
}

void print_entry(const AcceleratorInfo& info, std::size_t name_width) {
  fmt::print("\n  {:<{}}  {}\n", info.name, name_width, info.description);
  if (info.options.empty()) {
    fmt::print("      (no options)\n");
  } else {
    std::size_t key_width = 0;
    for (const auto& option : info.options) key_width = std::max(key_width, option.key.size());
    for (const auto& option : info.options) {
      std::string detail = fmt::format("{:<7}  default {}", to_string(option.type), option.default_value);
      if (!option.choices.empty()) detail += "  choices: " + joined(option.choices, "|");
      if (!option.range.empty()) detail += "  range " + option.range;
      fmt::print("      {:<{}}  {}  {}\n", option.key, key_width, detail, option.description);
    }
  }
  if (!info.variants.empty()) fmt::print("      variants: {}\n", joined(info.variants, "  "));
}

void print_structures() {
  const auto& registry = accelerator_registry();
  std::size_t name_width = 0, structure_count = 0;
  for (const auto& info : registry) {
    name_width = std::max(name_width, info.name.size());
    structure_count += info.comparison ? 0 : 1;
  }
  fmt::print("Structures ({}):\n", structure_count);
  for (const auto& info : registry) {
    if (!info.comparison) print_entry(info, name_width);
  }
  fmt::print("\nSpec syntax: NAME or NAME:key=value,key=value (e.g. --accel '{}')\n",
             accelerator_variant_names().back());
  if (structure_count == registry.size()) {
    fmt::print("Comparison: Embree was not found at build time; 'bench --compare embree' is unavailable\n");
  } else {
    fmt::print("\nComparison (other libraries: 'bench --compare embree', '--accel embree:quality=high,robust=1'; not "
               "in --names):\n");
    for (const auto& info : registry) {
      if (info.comparison) print_entry(info, name_width);
    }
  }
  fmt::print("\nBuilt-in scenes (builtin:NAME[:key=value,...]):\n");
  for (const auto& scene : builtin_scenes()) {
    std::vector<std::string> params;
    for (const auto& [key, value] : scene.defaults) params.push_back(key + "=" + value);
    fmt::print("  {:<16} {}{}\n", scene.name, scene.description,
               params.empty() ? "" : "  [" + joined(params, ",") + "]");
  }
}

}  // namespace

Command add_list_command(CLI::App& root) {
  auto names_only = std::make_shared<bool>(false);
  CLI::App* app = root.add_subcommand("list", "List the acceleration structures and their options");
  app->add_flag("--names", *names_only, "Print only the structure specs (every variant), one per line");
  return {app, [names_only] {
            if (*names_only) {
              for (const auto& name : accelerator_variant_names()) fmt::print("{}\n", name);
            } else {
              print_structures();
            }
            return 0;
          }};
}

}  // namespace rayaccel::cli
