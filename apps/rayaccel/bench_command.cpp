// `rayaccel bench SCENE...`: for each scene and structure, build time (median of 3 after a warm-up), memory,
// Mrays/s for primary, diffuse and shadow rays and for the primary rays in 4 x 2 pixel tiles traced as packets of
// eight (intersect_packets(); Embree: rtcIntersect8), traversal cost per ray, and a check of every answer against a
// reference before any timing; optionally an Embree row measured the same way, JSON, and images.
#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "bench.h"
#include "cli_common.h"
#include "commands.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/render/renderer.h"
#include "rayaccel/render/workloads.h"

namespace rayaccel::cli {

namespace {

struct BenchArgs {
  std::vector<std::string> scenes;
  std::string accel = "all";
  std::string rays = "primary,diffuse,shadow,packet";
  int resolution = 256;
  int threads = 0;
  int repeat = 5;
  std::string compare;
  std::string json;
  std::string images;
};

constexpr int kTimedBuilds = 3;
constexpr double kAffordableBuildMs = 2000.0;  // warm-up builds slower than this are the only build sample
constexpr double kCheapPassMs = 1000.0;        // trace passes faster than this get an untimed warm-up first
constexpr double kTraceBudgetMs = 5000.0;      // timed passes stop early once one workload has used this much
constexpr std::size_t kBruteForceSample = 2000;
constexpr float kShadowDistanceFraction = 0.1f;  // shadow ray length / scene box diagonal
constexpr std::uint64_t kDiffuseSeed = 1;
constexpr std::uint64_t kShadowSeed = 2;

/// What one scene's measurements share: the scene, its workloads, the reference check and the output options.
struct SceneContext {
  const Scene& scene;
  const Camera& camera;
  const std::vector<Workload>& workloads;
  const ReferenceCheck& check;
  const BenchArgs& args;
  int threads;
  Progress& progress;
};

std::vector<RayKind> parse_kinds(const std::string& text) {
  std::vector<RayKind> kinds;
  for (const auto& item : split_list(text)) {
    RayKind kind;
    if (item == "primary") {
      kind = RayKind::primary;
    } else if (item == "diffuse") {
      kind = RayKind::diffuse;
    } else if (item == "shadow") {
      kind = RayKind::shadow;
    } else if (item == "packet") {
      kind = RayKind::packet;
    } else {
      throw UsageError("--rays: unknown ray kind '" + item + "' (known: primary, diffuse, shadow, packet)");
    }
    if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end()) kinds.push_back(kind);
  }
  if (kinds.empty()) throw UsageError("--rays: '" + text + "' names no ray kind");
  return kinds;
}

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

void time_builds(const SceneContext& ctx, const std::string& spec, StructureResult& row,
                 std::unique_ptr<Accelerator>& accel) {
  accel = make_structure(spec, ctx.threads);
  const Stopwatch warm_up;
  accel->build(ctx.scene);
  const double warm_up_ms = warm_up.milliseconds();
  if (warm_up_ms > kAffordableBuildMs) {
    row.build_ms.push_back(warm_up_ms);
  } else {
    for (int i = 0; i < kTimedBuilds; ++i) {
      accel = make_structure(spec, ctx.threads);
      const Stopwatch clock;
      accel->build(ctx.scene);
      row.build_ms.push_back(clock.milliseconds());
    }
  }
  row.build_ms_median = median(row.build_ms);
}

void time_traces(const SceneContext& ctx, const Accelerator& accel, StructureResult& row) {
  for (std::size_t k = 0; k < ctx.workloads.size(); ++k) {
    const Workload& w = ctx.workloads[k];
    KindResult& result = row.kinds[k];
    ctx.progress.step(fmt::format("tracing {} {} rays", w.rays.size(), to_string(w.kind)));
    std::vector<Hit> hits(w.any_hit() ? 0 : w.rays.size());
    std::vector<std::uint8_t> occluded(w.any_hit() ? w.rays.size() : 0);
    const auto pass = [&] {
      const Stopwatch clock;
      if (w.any_hit()) {
        accel.occluded(w.rays, occluded);
      } else if (w.packets()) {
        accel.intersect_packets(w.rays, hits);
      } else {
        accel.intersect(w.rays, hits);
      }
      return clock.milliseconds();
    };
    // A warm-up pass (threads started, caches filled) is discarded unless it was slow enough to be a fair sample.
    const double warm_up_ms = pass();
    if (warm_up_ms > kCheapPassMs) result.trace_ms.push_back(warm_up_ms);
    double spent = warm_up_ms;
    while (static_cast<int>(result.trace_ms.size()) < ctx.args.repeat && spent < kTraceBudgetMs) {
      result.trace_ms.push_back(pass());
      spent += result.trace_ms.back();
      ctx.progress.update(static_cast<float>(result.trace_ms.size()) / static_cast<float>(ctx.args.repeat));
    }
    const double ms = median(result.trace_ms);
    result.mrays_s_median = ms > 0.0 ? static_cast<double>(w.rays.size()) / (ms * 1e3) : 0.0;
  }
}

/// An untimed pass with TraversalStats per ray: nodes visited and primitives tested per ray. Not for packet rays:
/// intersect_packets() takes no statistics.
void count_traversal(const SceneContext& ctx, const Accelerator& accel, StructureResult& row) {
  for (std::size_t k = 0; k < ctx.workloads.size(); ++k) {
    const Workload& w = ctx.workloads[k];
    if (w.packets()) continue;
    std::vector<TraversalStats> stats(w.rays.size());
    if (w.any_hit()) {
      std::vector<std::uint8_t> occluded(w.rays.size());
      accel.occluded(w.rays, occluded, stats);
    } else {
      std::vector<Hit> hits(w.rays.size());
      accel.intersect(w.rays, hits, stats);
    }
    TraversalStats total;
    for (const auto& s : stats) total += s;
    const double n = static_cast<double>(std::max<std::size_t>(w.rays.size(), 1));
    row.kinds[k].nodes_per_ray = static_cast<double>(total.nodes_visited) / n;
    row.kinds[k].prims_per_ray = static_cast<double>(total.primitives_tested) / n;
  }
}

void render_images(const SceneContext& ctx, const Accelerator& accel, const std::string& spec) {
  const std::filesystem::path dir(ctx.args.images);
  for (const auto mode : {ShadingMode::normals, ShadingMode::heatmap}) {
    const char* mode_name = mode == ShadingMode::normals ? "normals" : "heatmap";
    ctx.progress.step(fmt::format("rendering {}", mode_name));
    RenderSettings settings;
    settings.width = settings.height = ctx.args.resolution;
    settings.mode = mode;
    settings.progress = [&ctx](float fraction) { ctx.progress.update(fraction); };
    const RenderResult result = render(accel, ctx.scene, ctx.camera, settings);
    result.image.save_png(dir / (safe_file_name(ctx.scene.name()) + "_" + safe_file_name(spec) + "_" + mode_name +
                                 ".png"));
  }
}

StructureResult measure(const SceneContext& ctx, const std::string& spec, bool is_embree, std::size_t index,
                        std::size_t count) {
  ctx.progress.stage(fmt::format("{}: {} ({}/{})", ctx.scene.name(), spec, index, count));
  StructureResult row;
  row.spec = spec;
  row.is_embree = is_embree;
  for (const auto& w : ctx.workloads) {
    KindResult k;
    k.kind = w.kind;
    k.rays = w.rays.size();
    row.kinds.push_back(k);
  }
  try {
    ctx.progress.step("building");
    std::unique_ptr<Accelerator> accel;
    time_builds(ctx, spec, row, accel);
    row.memory_bytes = accel->memory_bytes();
    row.build_statistics = accel->build_statistics();
    ctx.progress.step("validating and checking against the reference");
    row.validate_problems = accel->validate();
    for (const auto& problem : row.validate_problems) {
      std::cerr << fmt::format("INVALID {} on {}: {}\n", spec, ctx.scene.name(), problem);
    }
    if (!is_embree) ctx.check.check(*accel, row.kinds);
    time_traces(ctx, *accel, row);
    if (!is_embree) {
      ctx.progress.step("counting traversal steps");
      count_traversal(ctx, *accel, row);
      if (!ctx.args.images.empty()) render_images(ctx, *accel, spec);
    }
  } catch (const std::exception& e) {
    row.failure = e.what();
    ctx.progress.done();
    std::cerr << fmt::format("FAILED {} on {}: {}\n", spec, ctx.scene.name(), e.what());
  }
  return row;
}

SceneReport bench_scene(const std::string& scene_spec, const std::vector<std::string>& specs,
                        const std::vector<RayKind>& kinds, const BenchArgs& args, Progress& progress) {
  progress.stage("loading " + scene_spec);
  const Scene scene = load_scene_checked(scene_spec);
  const Camera camera = default_camera(scene_spec, scene);
  const int threads = ThreadLimit::active();

  // Embree answers every reference query when it is built in; the measured row is only added with --compare.
  std::unique_ptr<Accelerator> embree;
#ifdef RAYACCEL_HAVE_EMBREE
  if (scene.kind() == PrimitiveKind::triangles) {
    progress.stage(fmt::format("{}: building the embree reference", scene.name()));
    embree = make_structure("embree", threads);
    embree->build(scene);
  }
#endif
  const bool compare_embree = args.compare == "embree";
  if (compare_embree && !embree) {
    std::cerr << fmt::format("warning: no embree row for {}: embree comparison supports triangle scenes only\n",
                             scene.name());
  }

  // The workloads: primary rays, then bounces from their hits (found by the reference, or by the first
  // structure when there is no Embree; every structure is checked on the same rays either way).
  progress.stage(fmt::format("{}: generating rays", scene.name()));
  std::vector<Workload> workloads;
  const std::vector<Ray> primary = primary_rays(camera, args.resolution, args.resolution);
  std::vector<Hit> primary_hits(primary.size());
  {
    std::unique_ptr<Accelerator> source;
    if (!embree) {
      source = make_structure(specs.front(), threads);
      source->build(scene);
    }
    (embree ? *embree : *source).intersect(primary, primary_hits);
  }
  const float diagonal = scene.bounds().is_empty() ? 1.0f : length(scene.bounds().extent());
  for (const RayKind kind : kinds) {
    Workload w;
    w.kind = kind;
    switch (kind) {
      case RayKind::primary: w.rays = primary; break;
      case RayKind::diffuse: w.rays = diffuse_rays(scene, primary, primary_hits, kDiffuseSeed); break;
      case RayKind::shadow:
        w.rays = shadow_rays(scene, primary, primary_hits, kShadowDistanceFraction * diagonal, kShadowSeed);
        break;
      case RayKind::packet:
        for (const std::size_t i : packet_tile_order(args.resolution, args.resolution)) w.rays.push_back(primary[i]);
        break;
    }
    workloads.push_back(std::move(w));
  }
  progress.stage(fmt::format("{}: computing reference answers", scene.name()));
  const ReferenceCheck check(scene, workloads, embree.get(), kBruteForceSample);

  SceneReport report;
  report.spec = scene_spec;
  report.name = scene.name();
  report.kind = to_string(scene.kind());
  report.primitives = scene.primitive_count();
  report.threads = threads;
  report.resolution = args.resolution;
  report.reference = check.description();
  const SceneContext ctx{scene, camera, workloads, check, args, threads, progress};
  const std::size_t count = specs.size() + (compare_embree && embree ? 1 : 0);
  if (compare_embree && embree) report.rows.push_back(measure(ctx, "embree", true, 1, count));
  for (const auto& spec : specs) report.rows.push_back(measure(ctx, spec, false, report.rows.size() + 1, count));
  progress.done();
  return report;
}

int run_bench(BenchArgs args, bool threads_given) {
  if (threads_given) require_range(args.threads, 1, 4096, "--threads");
  require_range(args.resolution, 1, 8192, "--res");
  require_range(args.repeat, 1, 1000000, "--repeat");
  const std::vector<RayKind> kinds = parse_kinds(args.rays);
  std::vector<std::string> specs = args.accel == "all" ? accelerator_variant_names() : split_specs(args.accel);
  if (specs.empty()) throw UsageError("--accel: '" + args.accel + "' names no structure");
  if (std::erase(specs, std::string("embree")) > 0) args.compare = "embree";
  if (specs.empty()) throw UsageError("--accel: name at least one structure besides embree");
  for (const auto& spec : specs) check_accelerator_spec(spec);
  if (!args.compare.empty() && args.compare != "embree") {
    throw UsageError("--compare: '" + args.compare + "' is not supported (only 'embree')");
  }
#ifndef RAYACCEL_HAVE_EMBREE
  if (!args.compare.empty()) throw UsageError("--compare embree: this build has no Embree (install libembree-dev)");
#endif
  for (const auto& scene : args.scenes) {
    std::error_code ec;
    if (scene.rfind("builtin:", 0) != 0 && !std::filesystem::is_regular_file(scene, ec)) {
      throw UsageError("scene file '" + scene + "' does not exist (or is not a file)");
    }
  }
  if (!args.json.empty()) check_output_path(args.json, "JSON file");
  if (!args.images.empty()) check_output_directory(args.images, "images");
  const ThreadLimit limit(threads_given ? args.threads : 0);

  Progress progress;
  nlohmann::json scenes = nlohmann::json::array();
  std::vector<std::string> failures;
  for (const auto& scene_spec : args.scenes) {
    const SceneReport report = bench_scene(scene_spec, specs, kinds, args, progress);
    print_table(report);
    scenes.push_back(to_json(report));
    for (const auto& row : report.rows) {
      if (row.failed()) failures.push_back(report.name + "/" + row.spec);
    }
  }
  if (!args.json.empty()) {
    write_file_atomically(args.json,
                          nlohmann::json{{"threads", ThreadLimit::active()}, {"scenes", scenes}}.dump(2) + "\n",
                          "JSON file");
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
  app->add_option("--accel", args->accel, "'all' or a comma list of structure specs")->capture_default_str();
  app->add_option("--rays", args->rays, "Ray kinds to time: primary, diffuse, shadow, packet (see below)")
      ->capture_default_str();
  app->add_option("--res", args->resolution, "Primary rays: an N x N image")->capture_default_str();
  CLI::Option* threads = app->add_option("--threads", args->threads, "Worker threads for builds and traces (>= 1)");
  app->add_option("--repeat", args->repeat, "Timed passes per ray kind (median reported)")->capture_default_str();
  app->add_option("--compare", args->compare, "Add a measured row for another library: embree");
  app->add_option("--json", args->json, "Write every figure to this JSON file");
  app->add_option("--images", args->images, "Render normals and heat-map PNGs per structure into this directory");
  app->footer(
      "Ray kinds: primary = one camera ray per pixel, row by row; diffuse = a cosine-weighted bounce from each\n"
      "primary hit; shadow = a short ambient-occlusion ray from each primary hit (any hit); packet = the primary\n"
      "rays reordered into 4x2 pixel tiles (tiles left to right, then top to bottom; when N is not a multiple of\n"
      "4, the pixels no whole tile covers follow in row order), each run of eight traced together with\n"
      "intersect_packets() (one by one by structures without a packet traversal; Embree: rtcIntersect8). Packet\n"
      "rays have no nodes/prims column: packet traversals take no statistics.");
  return {app, [args, threads] { return run_bench(*args, threads->count() > 0); }};
}

}  // namespace rayaccel::cli
