// `rayaccel trace SCENE RAYS --instances`: SCENE is read with its node hierarchy (a mesh used by several nodes is one
// geometry with several instances: import_instanced_scene()), each --geometry FILE adds one more geometry placed
// with the identity (several geometries side by side), and the rays are traced through an InstancedAccelerator.
// Output: .ihits, 24 bytes per ray (float32 t, uint32 prim_id, float32 u, float32 v, uint32 geom_id, uint32
// instance_id, little-endian; a miss: t = +inf, ids 0xFFFFFFFF, u = v = 0), or .occ with --occlusion.
#include "trace_instanced.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "cli_common.h"
#include "rayaccel/instance/import_instanced.h"
#include "rayaccel/instance/instance_hits_file.h"
#include "rayaccel/instance/instanced_accelerator.h"
#include "rayaccel/scene/ray_io.h"

namespace rayaccel::cli {

namespace {

/// SCENE with its instancing (a builtin scene: one geometry, placed once), then each --geometry with the identity.
InstancedScene load_instanced_scene(const InstancedTraceArgs& args) {
  InstancedScene scene;
  if (is_builtin(args.scene)) {
    scene.add_instance(scene.add_geometry(load_scene_checked(args.scene)), Affine3::identity());
  } else {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(std::filesystem::path(args.scene), ec)) {
      throw UsageError("scene file '" + args.scene + "' does not exist (or is not a file)");
    }
    scene = import_instanced_scene(args.scene);
  }
  for (const std::string& spec : args.geometries) {
    scene.add_instance(scene.add_geometry(load_scene_checked(spec)), Affine3::identity());
  }
  return scene;
}

}  // namespace

int run_trace_instanced(const InstancedTraceArgs& args, bool threads_given) {
  if (threads_given) require_range(args.threads, 1, 4096, "--threads");
  require_range(args.repeat, 1, 1000000, "--repeat");
  const std::string bottom = args.bottom.empty() ? InstancedAcceleratorOptions{}.bottom : args.bottom;
  check_accelerator_spec(bottom);
  const std::string top = args.top.empty() ? InstancedAcceleratorOptions{}.top : args.top;
  if (top != kTopLevelBvh) check_accelerator_spec(top);
  if (!args.out.empty()) check_output_path(args.out, args.occlusion ? "occlusion file" : "instance hit file");
  const ThreadLimit limit(threads_given ? args.threads : 0);

  const InstancedScene scene = load_instanced_scene(args);
  const std::vector<Ray> rays = read_rays(args.rays);

  InstancedAccelerator accel({bottom, top});
  const Stopwatch build_clock;
  accel.build(scene);
  const double build_ms = build_clock.milliseconds();

  std::vector<InstanceHit> hits(args.occlusion ? 0 : rays.size());
  std::vector<std::uint8_t> occluded(args.occlusion ? rays.size() : 0);
  std::vector<double> trace_ms;
  for (int i = 0; i < args.repeat; ++i) {
    const Stopwatch clock;
    if (args.occlusion) {
      accel.occluded(rays, occluded);
    } else {
      accel.intersect(rays, hits);
    }
    trace_ms.push_back(clock.milliseconds());
  }
  const std::size_t hit_count =
      args.occlusion ? static_cast<std::size_t>(std::count(occluded.begin(), occluded.end(), std::uint8_t{1}))
                     : static_cast<std::size_t>(std::count_if(hits.begin(), hits.end(), [](const InstanceHit& h) {
                         return h.found();
                       }));
  if (!args.out.empty()) {
    if (args.occlusion) {
      write_occlusion(args.out, occluded);
    } else {
      write_instance_hits(args.out, hits);
    }
  }

  const double trace_median = median(trace_ms);
  nlohmann::json summary = {
      {"accel", "instanced"},
      {"bottom", accel.bottom_spec()},
      {"top", accel.top_spec()},
      {"scene", args.scene},
      {"geometries", scene.geometry_count()},
      {"instances", scene.instance_count()},
      {"primitives", scene.flattened_primitive_count()},
      {"rays", rays.size()},
      {"query", args.occlusion ? "occluded" : "intersect"},
      {"threads", ThreadLimit::active()},
      {"build_ms", build_ms},
      {"trace_ms_median", trace_median},
      {"trace_ms", trace_ms},
      {"mrays_s_median", trace_median > 0.0 ? static_cast<double>(rays.size()) / (trace_median * 1e3) : 0.0},
      {"hit_count", hit_count},
      {"memory_bytes", accel.memory_bytes()},
      {"scene_memory_bytes", scene.memory_bytes()},
  };
  if (!args.out.empty()) summary["out"] = args.out;
  fmt::print("{}\n", summary.dump());
  return 0;
}

}  // namespace rayaccel::cli
