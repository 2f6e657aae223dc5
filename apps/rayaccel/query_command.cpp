// `rayaccel query MODE SCENE INPUT`: all-hits, count, closest, inside, winding and signed distance over a .rays or
// .points file; builds once, runs R times (median), prints one JSON summary line, --out writes the answers.
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "cli_common.h"
#include "commands.h"
#include "rayaccel/query/inside.h"
#include "rayaccel/query/signed_distance.h"
#include "rayaccel/scene/ray_io.h"

namespace rayaccel::cli {

namespace {

struct QueryArgs {
  std::string mode;
  std::string scene;
  std::string input;
  std::string accel;
  long long max_hits = 1 << 20;
  float max_distance = std::numeric_limits<float>::infinity();
  int parity_rays = 3;
  int threads = 0;
  int repeat = 3;
  std::string out;
  std::string counts;
};

const std::vector<std::string> kModes = {"all-hits", "count", "closest", "inside", "winding", "signed-distance"};

bool takes_rays(const std::string& mode) { return mode == "all-hits" || mode == "count"; }

std::string mode_list() {
  std::string text;
  for (const auto& m : kModes) text += (text.empty() ? "" : ", ") + m;
  return text;
}

/// Which options were given on the command line (a flag of another query is an error, not ignored).
struct GivenOptions {
  bool threads = false, max_hits = false, max_distance = false, parity_rays = false;
};

/// Throws UsageError when `flag` was given for a query it does not apply to.
void require_mode(const QueryArgs& args, bool given, const char* flag, std::initializer_list<const char*> modes) {
  if (!given) return;
  std::string names;
  for (const char* mode : modes) {
    if (args.mode == mode) return;
    names += (names.empty() ? "" : " and ") + std::string(mode);
  }
  throw UsageError(std::string(flag) + " applies to the " + names + " query only, not to " + args.mode);
}

int run_query(const QueryArgs& args, const GivenOptions& given) {
  if (std::find(kModes.begin(), kModes.end(), args.mode) == kModes.end()) {
    throw UsageError("unknown query '" + args.mode + "' (known: " + mode_list() + ")");
  }
  require_mode(args, given.max_hits, "--max-hits", {"all-hits"});
  require_mode(args, !args.counts.empty(), "--counts", {"all-hits"});
  require_mode(args, given.max_distance, "--max-distance", {"closest"});
  require_mode(args, given.parity_rays, "--parity-rays", {"inside", "signed-distance"});
  if (given.threads) require_range(args.threads, 1, 4096, "--threads");
  require_range(args.repeat, 1, 1000000, "--repeat");
  require_range(args.max_hits, 0, std::numeric_limits<std::uint32_t>::max(), "--max-hits");
  require_range(args.parity_rays, 1, 7, "--parity-rays");
  if (args.parity_rays % 2 == 0) throw UsageError("--parity-rays " + std::to_string(args.parity_rays) + " must be odd");
  if (!(args.max_distance >= 0.0f)) throw UsageError("--max-distance must be >= 0");
  const std::string spec = args.accel.empty() ? default_accelerator_spec() : args.accel;
  check_accelerator_spec(spec);
  if (!args.out.empty()) check_output_path(args.out, "query output file");
  if (!args.counts.empty()) check_output_path(args.counts, "count file");
  const ThreadLimit limit(given.threads ? args.threads : 0);

  auto accel = make_structure(spec, ThreadLimit::active());
  if (args.mode != "winding" && !accel->supports_queries()) {
    throw UsageError("'" + accel->spec() + "' does not answer " + args.mode +
                     " queries; use brute_force, bvh[:...] or bvh_wide[:...]");
  }
  const Scene scene = load_scene_checked(args.scene);
  std::vector<Ray> rays;
  std::vector<Vec3> points;
  if (takes_rays(args.mode)) {
    rays = read_rays(args.input);
  } else {
    points = read_points(args.input);
  }
  const std::size_t inputs = takes_rays(args.mode) ? rays.size() : points.size();

  const Stopwatch build_clock;
  if (args.mode != "winding") accel->build(scene);
  const double build_ms = build_clock.milliseconds();
  if (scene.kind() != PrimitiveKind::triangles) {
    throw UsageError("query " + args.mode + " needs a triangle scene; '" + args.scene + "' holds " +
                     to_string(scene.kind()));
  }

  std::vector<std::uint32_t> counts(rays.size());
  std::vector<Hit> all_hits;
  std::vector<ClosestPoint> closest(args.mode == "closest" || args.mode == "signed-distance" ? points.size() : 0);
  std::vector<std::uint8_t> inside(args.mode == "inside" ? points.size() : 0);
  std::vector<double> winding(args.mode == "winding" ? points.size() : 0);
  std::vector<float> distance(args.mode == "signed-distance" ? points.size() : 0);
  std::vector<double> query_ms;
  for (int r = 0; r < args.repeat; ++r) {
    const Stopwatch clock;
    if (args.mode == "count") {
      accel->count_hits(rays, counts);
    } else if (args.mode == "all-hits") {
      all_hits.clear();
      std::vector<Hit> one;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        counts[i] = static_cast<std::uint32_t>(accel->all_hits(rays[i], one, static_cast<std::size_t>(args.max_hits)));
        all_hits.insert(all_hits.end(), one.begin(), one.end());
      }
    } else if (args.mode == "closest") {
      accel->closest_points(points, closest, args.max_distance);
    } else if (args.mode == "inside") {
      inside_by_parity(*accel, points, inside, {.ray_count = args.parity_rays});
    } else if (args.mode == "winding") {
      winding_numbers(scene, points, winding);
    } else {
      signed_distances(*accel, points, distance, closest, {.ray_count = args.parity_rays});
    }
    query_ms.push_back(clock.milliseconds());
  }

  nlohmann::json summary = {{"query", args.mode},
                            {"accel", args.mode == "winding" ? "direct sum" : accel->spec()},
                            {"scene", scene.name()},
                            {"primitives", scene.primitive_count()},
                            {"inputs", inputs},
                            {"threads", ThreadLimit::active()},
                            {"build_ms", build_ms},
                            {"query_ms_median", median(query_ms)},
                            {"query_ms", query_ms}};
  const double seconds = median(query_ms) * 1e-3;
  summary["queries_per_s_median"] = seconds > 0.0 ? static_cast<double>(inputs) / seconds : 0.0;
  if (takes_rays(args.mode)) {
    std::uint64_t total = 0;
    for (std::uint32_t c : counts) total += c;
    summary["crossings"] = total;
  } else if (args.mode == "closest") {
    summary["found"] = std::count_if(closest.begin(), closest.end(), [](const ClosestPoint& c) { return c.found(); });
  } else if (args.mode == "inside") {
    summary["inside"] = std::count(inside.begin(), inside.end(), std::uint8_t{1});
  } else if (args.mode == "signed-distance") {
    summary["inside"] = std::count_if(distance.begin(), distance.end(), [](float d) { return d < 0.0f; });
  }
  if (!args.out.empty()) {
    if (args.mode == "all-hits") {
      write_hits(args.out, all_hits);
    } else if (args.mode == "count") {
      write_counts(args.out, counts);
    } else if (args.mode == "closest") {
      write_closest_points(args.out, closest);
    } else if (args.mode == "inside") {
      write_occlusion(args.out, inside);
    } else {
      std::vector<std::byte> bytes;
      if (args.mode == "winding") {
        bytes.resize(winding.size() * sizeof(double));
        std::memcpy(bytes.data(), winding.data(), bytes.size());
      } else {
        bytes.resize(distance.size() * sizeof(float));
        std::memcpy(bytes.data(), distance.data(), bytes.size());
      }
      write_file_atomically(args.out, bytes, "query output file");
    }
    summary["out"] = args.out;
  }
  if (!args.counts.empty()) {
    write_counts(args.counts, counts);
    summary["counts"] = args.counts;
  }
  fmt::print("{}\n", summary.dump());
  return 0;
}

}  // namespace

Command add_query_command(CLI::App& root) {
  auto args = std::make_shared<QueryArgs>();
  CLI::App* app = root.add_subcommand(
      "query", "Queries beyond the first hit: all-hits, count (.rays in); closest, inside, winding, signed-distance "
               "(.points in: float32 x y z)");
  app->add_option("mode", args->mode, "One of: " + mode_list())->required();
  app->add_option("scene", args->scene, "Mesh file or builtin:NAME[:key=value,...] (triangles)")->required();
  app->add_option("input", args->input, ".rays file (all-hits, count) or .points file (the others)")->required();
  app->add_option("--accel", args->accel,
                  "Structure spec: brute_force, bvh[:...] or bvh_wide[:...] (default " + default_accelerator_spec() +
                      "); winding sums over every triangle and builds nothing");
  CLI::Option* max_hits =
      app->add_option("--max-hits", args->max_hits, "all-hits: crossings kept per ray, the nearest")->capture_default_str();
  CLI::Option* max_distance =
      app->add_option("--max-distance", args->max_distance, "closest: search radius (default: unbounded)");
  CLI::Option* parity_rays =
      app->add_option("--parity-rays", args->parity_rays, "inside, signed-distance: rays per point (odd, 1..7)")
      ->capture_default_str();
  CLI::Option* threads = app->add_option("--threads", args->threads, "Worker threads for build and queries (>= 1)");
  app->add_option("--repeat", args->repeat, "Timed passes over all inputs (median reported)")->capture_default_str();
  app->add_option("--out", args->out,
                  "Answers: all-hits .hits records of every kept crossing in ray order (with --counts FILE: "
                  "uint32 crossings per ray); count .counts; closest .closest (28 bytes: x y z distance prim u v); "
                  "inside 1 byte per point; winding float64 and signed-distance float32 per point");
  app->add_option("--counts", args->counts, "all-hits: uint32 crossings per ray (before --max-hits)");
  return {app, [args, threads, max_hits, max_distance, parity_rays] {
            return run_query(*args, {threads->count() > 0, max_hits->count() > 0, max_distance->count() > 0,
                                     parity_rays->count() > 0});
          }};
}

}  // namespace rayaccel::cli
