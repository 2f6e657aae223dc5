// `rayaccel bench SCENE...`: for each scene and structure, build time (median of 3 after a warm-up, plus the scene
// preparation), memory, Mrays/s for primary, diffuse, shadow, occlusion and light rays and for the primary and
// light rays in 4 x 2 pixel tiles traced as packets of eight (intersect_packets(), occluded_packets(); Embree:
// rtcIntersect8, rtcOccluded8), traversal cost per ray,
// and a check of every answer against a reference before any timing; optionally an Embree row (measured before and
// after the structures), JSON, and images.
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
  std::string rays = "primary,diffuse,shadow,occlusion,light,packet,light_packet";
  int resolution = 256;
  int threads = 0;
  int repeat = 5;
  std::string compare;
  std::string json;
  std::string images;
  std::uint64_t heat_max = 0;  ///< 0: every heat map of the run on one shared scale, drawn at the end
};

/// A heat map waiting for the run's shared colour scale.
struct PendingHeatMap {
  std::filesystem::path file;
  HeatFrame frame;
};

/// Heat-map data the bench may hold for the shared scale before it asks for --heat-max instead.
constexpr std::size_t kHeatFrameBudgetBytes = std::size_t{1} << 30;

constexpr int kTimedBuilds = 3;
constexpr double kAffordableBuildMs = 2000.0;  // warm-up builds slower than this are the only build sample
constexpr double kCheapPassMs = 1000.0;        // trace passes faster than this get an untimed warm-up first
constexpr double kTraceBudgetMs = 5000.0;      // timed passes stop early once one workload has used this much
constexpr std::size_t kBruteForceSample = 2000;
// Beside Embree, brute force's sample per ray kind is smaller: it only has to catch a structure that agrees with
// Embree where both are wrong (2,000 rays of two kinds cost 160 s of CPU on the dragon, 871k triangles).
constexpr std::size_t kBruteForceSampleBesideEmbree = 256;
constexpr float kShadowDistanceFraction = 0.1f;     // shadow ray length / scene box diagonal
constexpr float kOcclusionDistanceFraction = 0.25f; // occlusion ray length / scene box diagonal
constexpr float kFixedOffsetFraction = 1e-4f;       // occlusion rays' origin offset / scene box diagonal
constexpr float kLightHeightFraction = 0.45f;       // light above the box center along the camera's up / extent
constexpr std::uint64_t kDiffuseSeed = 1;
constexpr std::uint64_t kShadowSeed = 2;
constexpr std::uint64_t kOcclusionSeed = 3;

/// What one scene's measurements share: the scene, its workloads, the reference check and the output options.
struct SceneContext {
  const Scene& scene;
  const Camera& camera;
  const std::vector<Workload>& workloads;
  const ReferenceCheck& check;
  const BenchArgs& args;
  int threads;
  Progress& progress;
  std::vector<PendingHeatMap>& heat_maps;  ///< filled when the heat maps share the run's scale
  double scene_preparation_ms;             ///< added to rayaccel's build times (see scene_preparation_ms())
};

/// The point light of the light rays: above the center of the scene's box along the camera's up direction, inside
/// the box (near the ceiling of a room, above an object).
Vec3 light_position(const Scene& scene, const Camera& camera) {
  if (scene.bounds().is_empty()) return {};
  const Vec3 up = normalize(camera.up);
  const Vec3 extent = scene.bounds().extent();
  const float height = std::abs(up.x) * extent.x + std::abs(up.y) * extent.y + std::abs(up.z) * extent.z;
  return scene.bounds().center() + up * (kLightHeightFraction * height);
}

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
    } else if (item == "occlusion") {
      kind = RayKind::occlusion;
    } else if (item == "light") {
      kind = RayKind::light;
    } else if (item == "packet") {
      kind = RayKind::packet;
    } else if (item == "light_packet") {
      kind = RayKind::light_packet;
    } else {
      throw UsageError("--rays: unknown ray kind '" + item +
                       "' (known: primary, diffuse, shadow, occlusion, light, packet, light_packet)");
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
  row.build_ms_median = median(row.build_ms) + (row.is_embree ? 0.0 : ctx.scene_preparation_ms);
}

double mrays_per_second(std::size_t rays, const std::vector<double>& trace_ms) {
  const double ms = median(trace_ms);
  return ms > 0.0 ? static_cast<double>(rays) / (ms * 1e3) : 0.0;
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
      if (w.any_hit() && w.packets()) {
        accel.occluded_packets(w.rays, occluded);
      } else if (w.any_hit()) {
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
    result.mrays_s_median = mrays_per_second(w.rays.size(), result.trace_ms);
  }
}

/// An untimed pass with TraversalStats per ray: nodes visited and primitives tested per ray. Not for packet rays:
/// intersect_packets() and occluded_packets() take no statistics.
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

std::filesystem::path image_file(const SceneContext& ctx, const std::string& spec, const char* mode_name) {
  return std::filesystem::path(ctx.args.images) /
         (safe_file_name(ctx.scene.name()) + "_" + safe_file_name(spec) + "_" + mode_name + ".png");
}

/// Writes the normals image now; the heat map too when --heat-max fixes its scale, else keeps its frame for
/// write_shared_heat_maps().
void render_images(const SceneContext& ctx, const Accelerator& accel, const std::string& spec) {
  for (const auto mode : {ShadingMode::normals, ShadingMode::heatmap}) {
    const char* mode_name = mode == ShadingMode::normals ? "normals" : "heatmap";
    ctx.progress.step(fmt::format("rendering {}", mode_name));
    RenderSettings settings;
    settings.width = settings.height = ctx.args.resolution;
    settings.mode = mode;
    if (ctx.args.heat_max > 0) settings.heat_scale = fixed_heat_scale(ctx.args.heat_max);
    settings.progress = [&ctx](float fraction) { ctx.progress.update(fraction); };
    RenderResult result = render(accel, ctx.scene, ctx.camera, settings);
    if (mode == ShadingMode::heatmap && ctx.args.heat_max == 0) {
      ctx.heat_maps.push_back({image_file(ctx, spec, mode_name), std::move(result.heat)});
    } else {
      result.image.save_png(image_file(ctx, spec, mode_name));
    }
  }
}

/// Draws every kept heat map on one scale, the shared_cost_range() of all of them, and writes them.
void write_shared_heat_maps(std::vector<PendingHeatMap>& heat_maps, Progress& progress) {
  if (heat_maps.empty()) return;
  std::vector<const HeatFrame*> frames;
  for (const auto& h : heat_maps) frames.push_back(&h.frame);
  const CostRange scale = shared_cost_range(frames);
  progress.stage(fmt::format("writing {} heat maps on one scale, cost {} to {}", heat_maps.size(), scale.min,
                             scale.max));
  for (auto& h : heat_maps) {
    draw_heat_frame(h.frame, scale).save_png(h.file);
    h.frame = {};
  }
  progress.done();
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
    row.input_memory_bytes = accel->input_memory_bytes(ctx.scene);
    row.build_statistics = accel->build_statistics();
    ctx.progress.step("validating and checking against the reference");
    row.validate_problems = accel->validate();
    for (const auto& problem : row.validate_problems) {
      std::cerr << fmt::format("INVALID {} on {}: {}\n", spec, ctx.scene.name(), problem);
    }
    if (is_embree) {
      ctx.check.check_foreign(*accel, row.kinds);
    } else {
      ctx.check.check(*accel, row.kinds);
    }
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

/// Embree is measured before and after rayaccel's structures, so that a drift in the machine's speed during the
/// run favours neither side; its row pools the samples of both measurements.
void pool_measurements(StructureResult& row, const StructureResult& again) {
  if (!again.failure.empty() || !row.failure.empty()) {
    if (row.failure.empty()) row.failure = again.failure;
    return;
  }
  row.build_ms.insert(row.build_ms.end(), again.build_ms.begin(), again.build_ms.end());
  row.build_ms_median = median(row.build_ms);
  for (std::size_t k = 0; k < row.kinds.size(); ++k) {
    KindResult& kind = row.kinds[k];
    kind.trace_ms.insert(kind.trace_ms.end(), again.kinds[k].trace_ms.begin(), again.kinds[k].trace_ms.end());
    kind.mrays_s_median = mrays_per_second(kind.rays, kind.trace_ms);
  }
}

/// The per-pixel values of an N x N image (row by row) reordered into packet_tile_order(), as the packet kinds take
/// their rays.
template <class T>
std::vector<T> in_tile_order(const std::vector<T>& per_pixel, int resolution) {
  std::vector<T> tiled;
  tiled.reserve(per_pixel.size());
  for (const std::size_t i : packet_tile_order(resolution, resolution)) tiled.push_back(per_pixel[i]);
  return tiled;
}

/// Median time to prepare the scene from its mesh (per-primitive vertices, bounds and validity), the work Embree
/// does inside its build: rayaccel's structures get it added to their build times, so both sides count it.
double scene_preparation_ms(const Scene& scene) {
  if (scene.kind() != PrimitiveKind::triangles || scene.borrows_buffers()) return 0.0;
  std::vector<double> samples;
  for (int i = 0; i < kTimedBuilds; ++i) {
    TriangleMesh copy = scene.mesh();
    const Stopwatch clock;
    const Scene prepared = Scene::from_mesh(std::move(copy), scene.name());
    samples.push_back(clock.milliseconds());
  }
  return median(samples);
}

SceneReport bench_scene(const std::string& scene_spec, const std::vector<std::string>& specs,
                        const std::vector<RayKind>& kinds, const BenchArgs& args, Progress& progress,
                        std::vector<PendingHeatMap>& heat_maps) {
  progress.stage("loading " + scene_spec);
  const Scene scene = load_scene_checked(scene_spec);
  const Camera camera = default_camera(scene_spec, scene);
  const int threads = ThreadLimit::active();

  // Embree answers every reference query when it is built in; the measured row is only added with --compare.
  std::unique_ptr<Accelerator> embree;
  if (has_accelerator("embree") && scene.kind() == PrimitiveKind::triangles) {
    progress.stage(fmt::format("{}: building the embree reference", scene.name()));
    embree = make_structure("embree", threads);
    embree->build(scene);
  }
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
      case RayKind::occlusion:
        w.rays = shadow_rays(scene, primary, primary_hits, kOcclusionDistanceFraction * diagonal, kOcclusionSeed,
                             OriginOffset{kFixedOffsetFraction * diagonal});
        break;
      case RayKind::light: w.rays = light_rays(scene, primary, primary_hits, light_position(scene, camera)); break;
      case RayKind::packet: w.rays = in_tile_order(primary, args.resolution); break;
      case RayKind::light_packet:
        // The light rays of the primary hits taken in tile order: the same rays as `light`, neighbours together.
        w.rays = light_rays(scene, in_tile_order(primary, args.resolution),
                            in_tile_order(primary_hits, args.resolution), light_position(scene, camera));
        break;
    }
    workloads.push_back(std::move(w));
  }
  progress.stage(fmt::format("{}: computing reference answers", scene.name()));
  const ReferenceCheck check(scene, workloads, embree.get(),
                             embree ? kBruteForceSampleBesideEmbree : kBruteForceSample);

  SceneReport report;
  report.spec = scene_spec;
  report.name = scene.name();
  report.kind = to_string(scene.kind());
  report.primitives = scene.primitive_count();
  report.threads = threads;
  report.resolution = args.resolution;
  report.reference = check.description();
  report.scene_preparation_ms = scene_preparation_ms(scene);
  const SceneContext ctx{scene, camera, workloads, check, args, threads, progress, heat_maps,
                         report.scene_preparation_ms};
  const bool embree_row = compare_embree && embree;
  const std::size_t count = specs.size() + (embree_row ? 2 : 0);
  if (embree_row) report.rows.push_back(measure(ctx, "embree", true, 1, count));
  for (const auto& spec : specs) {
    report.rows.push_back(measure(ctx, spec, is_comparison_spec(spec), report.rows.size() + 1, count));
  }
  if (embree_row) pool_measurements(report.rows.front(), measure(ctx, "embree", true, count, count));
  progress.done();
  return report;
}

int run_bench(BenchArgs args, bool threads_given, bool heat_max_given) {
  if (threads_given) require_range(args.threads, 1, 4096, "--threads");
  if (heat_max_given) require_heat_max(args.heat_max);
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
  if (!args.compare.empty() && !has_accelerator("embree")) {
    throw UsageError("--compare embree: this build has no Embree (install libembree-dev)");
  }
  for (const auto& scene : args.scenes) {
    std::error_code ec;
    if (scene.rfind("builtin:", 0) != 0 && !std::filesystem::is_regular_file(scene, ec)) {
      throw UsageError("scene file '" + scene + "' does not exist (or is not a file)");
    }
  }
  if (!args.json.empty()) check_output_path(args.json, "JSON file");
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
  nlohmann::json scenes = nlohmann::json::array();
  std::vector<std::string> failures;
  std::vector<PendingHeatMap> heat_maps;
  for (const auto& scene_spec : args.scenes) {
    const SceneReport report = bench_scene(scene_spec, specs, kinds, args, progress, heat_maps);
    print_table(report);
    scenes.push_back(to_json(report));
    for (const auto& row : report.rows) {
      if (row.failed()) failures.push_back(report.name + "/" + row.spec);
    }
  }
  write_shared_heat_maps(heat_maps, progress);
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
      "Memory: 'memory MB' is the structure's own data; 'with input MB' adds the input its queries read (the\n"
      "scene's arrays for rayaccel's structures; for Embree, the vertex and index buffers it was handed).");
  return {app, [args, threads, heat_max] { return run_bench(*args, threads->count() > 0, heat_max->count() > 0); }};
}

}  // namespace rayaccel::cli
