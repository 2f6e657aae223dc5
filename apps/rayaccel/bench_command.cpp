// `rayaccel bench SCENE...`: its options, their checks before any work, and the run over the scenes (measured by
// bench_run.cpp) with its outputs: tables, JSON, images and the HTML report.
#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "bench.h"
#include "cli_common.h"
#include "commands.h"
#include "rayaccel/accel/registry.h"

namespace rayaccel::cli {

namespace {

/// Heat-map data the bench may hold for the shared scale before it asks for --heat-max instead.
constexpr std::size_t kHeatFrameBudgetBytes = std::size_t{1} << 30;

/// Splits "a,b:k=v,k2=v2,c" into structure specs: an item of the form key=value continues the previous spec.
std::vector<std::string> split_specs(const std::string& text) {
  std::vector<std::string> specs;
  for (const auto& item : split_list(text)) {
    const bool continues = item.find('=') != std::string::npos && item.find(':') == std::string::npos;
    if (continues && !specs.empty()) {
      specs.back() += "," + item;
    } else {
      specs.push_back(item);
    }
  }
  return specs;
}

/// The structures --accel names: the default structure when it is not given, every variant for "all".
std::vector<std::string> structure_specs(BenchArgs& args) {
  std::vector<std::string> specs;
  if (args.accel.empty()) {
    specs = {default_accelerator_spec()};
  } else if (args.accel == "all") {
    specs = accelerator_variant_names();
  } else {
    specs = split_specs(args.accel);
  }
  if (specs.empty()) throw UsageError("--accel: '" + args.accel + "' names no structure");
  if (std::erase(specs, std::string("embree")) > 0) args.compare = "embree";
  if (specs.empty()) throw UsageError("--accel: name at least one structure besides embree");
  for (const auto& spec : specs) check_accelerator_spec(spec);
  return specs;
}

int run_bench(BenchArgs args, bool threads_given, bool heat_max_given) {
  if (threads_given) require_range(args.threads, 1, 4096, "--threads");
  if (heat_max_given) require_heat_max(args.heat_max);
  require_range(args.resolution, 1, 8192, "--res");
  require_range(args.repeat, 1, 1000000, "--repeat");
  const std::vector<RayKind> kinds = parse_kinds(args.rays);
  const std::vector<std::string> specs = structure_specs(args);
  if (!args.compare.empty() && args.compare != "embree") {
    throw UsageError("--compare: '" + args.compare + "' is not supported (only 'embree')");
  }
  if (!args.compare.empty() && !has_accelerator("embree")) {
    throw UsageError("--compare embree: this build has no Embree (install libembree-dev)");
  }
  for (const auto& scene : args.scenes) check_scene_exists(scene);
  if (!args.json.empty()) check_output_path(args.json, "JSON file");
  if (!args.report.empty()) {
    check_output_directory(args.report, "report");
    if (args.images.empty()) args.images = (std::filesystem::path(args.report) / "images").string();
  }
  if (!args.images.empty()) {
    const std::size_t frame_bytes = static_cast<std::size_t>(args.resolution) * args.resolution *
                                    kSharedHeatBytesPerPixel * specs.size() * args.scenes.size();
    if (args.heat_max == 0 && frame_bytes > kHeatFrameBudgetBytes) {
      throw UsageError(fmt::format(
          "--images: one colour scale for {} heat maps of {}x{} means holding {:.1f} GiB until the end of the run; "
          "pass --heat-max to draw each heat map on a fixed scale as it is rendered",
          specs.size() * args.scenes.size(), args.resolution, args.resolution,
          static_cast<double>(frame_bytes) / static_cast<double>(std::size_t{1} << 30)));
    }
    check_output_directory(args.images, "images");
  }
  const ThreadLimit limit(threads_given ? args.threads : 0);

  Progress progress;
  std::vector<SceneReport> reports;
  std::vector<std::string> failures;
  std::vector<PendingHeatMap> heat_maps;
  for (const auto& scene_spec : args.scenes) {
    reports.push_back(bench_scene(scene_spec, specs, kinds, args, progress, heat_maps));
    print_table(reports.back());
    for (const auto& row : reports.back().rows) {
      if (row.failed()) failures.push_back(reports.back().name + "/" + row.spec);
    }
  }
  CostRange heat = write_shared_heat_maps(heat_maps, progress);
  if (args.heat_max > 0) heat = fixed_heat_scale(args.heat_max);
  nlohmann::json scenes = nlohmann::json::array();
  for (const auto& report : reports) scenes.push_back(to_json(report));
  const std::string json = nlohmann::json{{"threads", ThreadLimit::active()},
                                          {"default_accel", default_accelerator_spec()},
                                          {"scenes", scenes}}.dump(2) + "\n";
  if (!args.json.empty()) write_file_atomically(args.json, json, "JSON file");
  if (!args.report.empty()) {
    const std::filesystem::path dir = args.report;
    write_file_atomically(dir / "bench.json", json, "JSON file");
    write_html_report(dir, reports, std::filesystem::path(args.images).lexically_proximate(dir), heat, args);
    fmt::print("\nreport: {}\n", (dir / "index.html").string());
  }
  if (!failures.empty()) {
    std::string list;
    for (const auto& f : failures) list += (list.empty() ? "" : ", ") + f;
    std::cerr << fmt::format("rayaccel bench: FAILED: {} structure(s) mismatched, failed or are invalid: {}\n",
                             failures.size(), list);
    return kExitRuntime;
  }
  return 0;
}

}  // namespace

Command add_bench_command(CLI::App& root) {
  auto args = std::make_shared<BenchArgs>();
  CLI::App* app = root.add_subcommand("bench", "Compare structures: build time, memory, Mrays/s, traversal cost");
  app->add_option("scenes", args->scenes, "Mesh files or builtin:NAME[:key=value,...]")->required();
  app->add_option("--accel", args->accel,
                  "Structures to measure: a comma list of specs, or 'all' for every variant of `rayaccel list "
                  "--names` (default: the default structure, " + default_accelerator_spec() + ")");
  app->add_option("--rays", args->rays, "Ray kinds to time: primary, diffuse, shadow, packet, ... (see below)")
      ->capture_default_str();
  app->add_option("--res", args->resolution, "Primary rays: an N x N image")->capture_default_str();
  CLI::Option* threads = app->add_option("--threads", args->threads, "Worker threads for builds and traces (>= 1)");
  app->add_option("--repeat", args->repeat, "Timed passes per ray kind (median reported)")->capture_default_str();
  app->add_option("--compare", args->compare, "Add a measured row for another library: embree");
  app->add_option("--json", args->json, "Write every figure to this JSON file");
  app->add_option("--images", args->images,
                  "Render normals and heat-map PNGs per structure into this directory (every heat map of the run on "
                  "one colour scale, written at the end, unless --heat-max is given)");
  app->add_option("--report", args->report,
                  "Write DIR/index.html, one page with the tables, charts and every structure's images (in "
                  "DIR/images unless --images is given), viewable offline, and DIR/bench.json");
  CLI::Option* heat_max = app->add_option("--heat-max", args->heat_max, kHeatMaxHelp);
  app->footer(
      "Ray kinds: primary = one camera ray per pixel, row by row; diffuse = a cosine-weighted bounce from each\n"
      "primary hit; shadow = an ambient-occlusion ray of 0.1 scene diagonals from each primary hit (any hit),\n"
      "starting at pbrt's conservative offset; occlusion = the same of 0.25 diagonals, starting 1e-4 diagonals off\n"
      "the surface along the normal (the fixed epsilon many renderers use); light = a shadow ray from each primary\n"
      "hit to a point light above the scene's center (any hit); packet = the primary\n"
      "rays reordered into 4x2 pixel tiles (tiles left to right, then top to bottom; when N is not a multiple of\n"
      "4, the pixels no whole tile covers follow in row order), each run of eight traced together with\n"
      "intersect_packets() (one by one by structures without a packet traversal; Embree: rtcIntersect8);\n"
      "light_packet = the light rays of the primary hits in that tile order (pixels that miss have none), each run\n"
      "of eight traced together with occluded_packets() (Embree: rtcOccluded8). Packet rays have no nodes/prims\n"
      "column: packet traversals take no statistics.\n"
      "Not in the default set: diffuse_skip, shadow_skip, occlusion_skip and light_skip = the same rays traced\n"
      "with a QueryContext that skips the primitive each ray starts on (Embree: an intersection filter that\n"
      "rejects it, its scene committed with RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION, the row then named\n"
      "embree:filter=1 for every kind); no nodes/prims column either. beam = the primary rays traced by the\n"
      "structure's beams, the whole image in one call (bvh_wide: frustum beams, the rays left over in 4x2 packets\n"
      "from each tile's entry point; bvh, kdtree: the double-precision beams); structures without beams and\n"
      "Embree trace the same rays eight at a time in row order (Embree: rtcIntersect8); no nodes/prims column.\n"
      "Memory: 'memory MB' is the structure's own data; 'with input MB' adds the input its queries read (the\n"
      "scene's arrays for rayaccel's structures; for Embree, the vertex and index buffers it was handed).");
  return {app, [args, threads, heat_max] { return run_bench(*args, threads->count() > 0, heat_max->count() > 0); }};
}

}  // namespace rayaccel::cli
