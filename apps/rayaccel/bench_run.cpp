// Measuring one scene for `rayaccel bench`: the reference and the workloads, then per structure the builds (median
// of 3 after a warm-up), memory, a check of every answer, the timed trace passes, traversal statistics and images.
#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "bench.h"
#include "cli_common.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/render/renderer.h"
#include "rayaccel/render/workloads.h"

namespace rayaccel::cli {

namespace {

constexpr int kTimedBuilds = 3;
constexpr double kAffordableBuildMs = 2000.0;  // warm-up builds slower than this are the only build sample
constexpr double kCheapPassMs = 1000.0;        // trace passes faster than this get an untimed warm-up first
constexpr double kTraceBudgetMs = 5000.0;      // timed passes stop early once one workload has used this much
constexpr std::size_t kBruteForceSample = 2000;
// Beside Embree, brute force's sample per ray kind is smaller: it only has to catch a structure that agrees with
// Embree where both are wrong (2,000 rays of two kinds cost 160 s of CPU on the dragon, 871k triangles).
constexpr std::size_t kBruteForceSampleBesideEmbree = 256;

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

void time_builds(const SceneContext& ctx, const std::string& spec, StructureResult& row,
                 std::unique_ptr<Accelerator>& accel) {
  ctx.progress.step("building");
  accel = make_structure(spec, ctx.threads);
  const Stopwatch warm_up;
  accel->build(ctx.scene);
  const double warm_up_ms = warm_up.milliseconds();
  if (warm_up_ms > kAffordableBuildMs) {
    row.build_ms.push_back(warm_up_ms);
  } else {
    for (int i = 0; i < kTimedBuilds; ++i) {
      ctx.progress.step(fmt::format("building ({} of {} timed)", i + 1, kTimedBuilds));
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
      trace_rays(accel, w, w.rays, w.skip, hits, occluded, w.packets());
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

/// An untimed pass with TraversalStats per ray: nodes visited and primitives tested per ray. Not for packet rays and
/// the _skip kinds: intersect_packets(), occluded_packets() and the queries with a context take no statistics.
void count_traversal(const SceneContext& ctx, const Accelerator& accel, StructureResult& row) {
  for (std::size_t k = 0; k < ctx.workloads.size(); ++k) {
    const Workload& w = ctx.workloads[k];
    if (w.packets() || w.skips()) continue;
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
  return std::filesystem::path(ctx.args.images) / bench_image_name(ctx.scene.name(), spec, mode_name);
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

}  // namespace

std::string bench_embree_spec(const std::vector<RayKind>& kinds) {
  const bool skips = std::any_of(kinds.begin(), kinds.end(), is_skip_kind);
  return skips ? kEmbreeWithFilter : "embree";
}

std::string bench_image_name(const std::string& scene_name, const std::string& spec, const char* mode_name) {
  return safe_file_name(scene_name) + "_" + safe_file_name(spec) + "_" + mode_name + ".png";
}

CostRange write_shared_heat_maps(std::vector<PendingHeatMap>& heat_maps, Progress& progress) {
  if (heat_maps.empty()) return {};
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
  return scale;
}

SceneReport bench_scene(const std::string& scene_spec, const std::vector<std::string>& specs,
                        const std::vector<RayKind>& kinds, const BenchArgs& args, Progress& progress,
                        std::vector<PendingHeatMap>& heat_maps) {
  progress.stage("loading " + scene_spec);
  const Scene scene = load_scene_checked(scene_spec);
  const Camera camera = default_camera(scene_spec, scene);
  const int threads = ThreadLimit::active();

  // Embree answers every reference query when it is built in (it builds in a fraction of a second where brute
  // force's sample would take minutes on a large scene); the measured row is only added with --compare.
  std::unique_ptr<Accelerator> embree;
  const std::string embree_spec = bench_embree_spec(kinds);
  if (has_accelerator("embree") && scene.kind() == PrimitiveKind::triangles) {
    progress.stage(fmt::format("{}: building the embree reference that checks the answers (not timed)",
                               scene.name()));
    embree = make_structure(embree_spec, threads);
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
  const std::vector<Workload> workloads =
      make_workloads(scene, camera, kinds, args.resolution, primary, primary_hits);
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
  if (embree_row) report.rows.push_back(measure(ctx, embree_spec, true, 1, count));
  for (const auto& spec : specs) {
    report.rows.push_back(measure(ctx, spec, is_comparison_spec(spec), report.rows.size() + 1, count));
  }
  if (embree_row) pool_measurements(report.rows.front(), measure(ctx, embree_spec, true, count, count));
  progress.done();
  return report;
}

}  // namespace rayaccel::cli
