// `rayaccel trace SCENE RAYS --instances`: SCENE read with its node hierarchy (plus --geometry files placed with the
// identity), traced through an InstancedAccelerator into .ihits (instance/instance_hits_file.h) or .occ.
#include "trace_instanced.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "cli_common.h"
#include "trace_passes.h"
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

  const TracePasses passes = run_trace_passes<InstanceHit>(
      rays.size(), args.occlusion, args.repeat, args.out,
      [&](std::span<InstanceHit> hits) { accel.intersect(rays, hits); },
      [&](std::span<std::uint8_t> occluded) { accel.occluded(rays, occluded); },
      [](const std::string& path, std::span<const InstanceHit> hits) { write_instance_hits(path, hits); });

  nlohmann::json summary = trace_summary({
      .accel = "instanced",
      .scene = args.scene,
      .primitives = scene.flattened_primitive_count(),
      .rays = rays.size(),
      .query = args.occlusion ? "occluded" : "intersect",
      .trace_ms = passes.trace_ms,
      .hit_count = passes.hit_count,
      .memory_bytes = accel.memory_bytes(),
      .scene_memory_bytes = scene.memory_bytes(),
      .input_memory_bytes = scene.memory_bytes(),  // the bottom levels read their geometries' arrays
  });
  summary["bottom"] = accel.bottom_spec();
  summary["top"] = accel.top_spec();
  summary["geometries"] = scene.geometry_count();
  summary["instances"] = scene.instance_count();
  summary["build_ms"] = build_ms;
  if (!args.out.empty()) summary["out"] = args.out;
  fmt::print("{}\n", summary.dump());
  return 0;
}

}  // namespace rayaccel::cli
