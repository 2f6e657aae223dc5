// `rayaccel trace SCENE RAYS --precision double`: the scene in double (load_mesh_double) moved by --offset, a
// double structure (brute_force or bvh with bv=aabb), .rays64 in, .hits64 or .occ out, and the float trace's
// summary line plus "precision":"double".
#include "trace_double.h"

#include <fmt/core.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cli_common.h"
#include "trace_passes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/core/ray_d.h"
#include "rayaccel/double/double_accelerator.h"
#include "rayaccel/double/double_scene.h"
#include "rayaccel/double/double_scene_load.h"
#include "rayaccel/scene/ray_io.h"

namespace rayaccel::cli {

namespace {

/// Throws UsageError unless `spec` names a structure with a double version and valid options.
void check_double_spec(const std::string& spec) {
  std::string name;
  try {
    name = parse_accelerator_spec(spec).name;
  } catch (const Error& e) {
    throw UsageError("--accel: " + std::string(e.what()));
  }
  const std::vector<std::string> known = double_accelerator_names();
  if (std::find(known.begin(), known.end(), name) == known.end()) {
    throw UsageError("--precision double: structure '" + name + "' has no double-precision version (double: " +
                     "brute_force, bvh[:key=value,...] with bv=aabb)");
  }
  try {
    make_double_accelerator(spec);
  } catch (const Error& e) {
    throw UsageError("--accel: " + std::string(e.what()));
  }
}

}  // namespace

int run_trace_double(const TraceDoubleArgs& args) {
  const std::string spec = args.accel.empty() ? "bvh" : args.accel;
  check_double_spec(spec);
  const DVec3 offset = args.offset.empty() ? DVec3{} : parse_dvec3(args.offset, "--offset");
  if (!args.out.empty()) check_output_path(args.out, args.occlusion ? "occlusion file" : "hit file");

  check_scene_exists(args.scene);
  NamedMeshD loaded = load_mesh_double(args.scene, offset);
  const std::string name = loaded.name;
  const DoubleScene scene(std::move(loaded.mesh));
  const std::vector<RayD> rays = read_rays_d(args.rays);

  std::vector<double> build_ms;
  std::unique_ptr<DoubleAccelerator> accel;
  for (int i = 0; i < kTraceBuilds; ++i) {
    accel = make_double_accelerator(spec);
    const Stopwatch clock;
    accel->build(scene);
    build_ms.push_back(clock.milliseconds());
  }

  const TracePasses passes = run_trace_passes<HitD>(
      rays.size(), args.occlusion, args.repeat, args.out, [&](std::span<HitD> hits) { accel->intersect(rays, hits); },
      [&](std::span<std::uint8_t> occluded) { accel->occluded(rays, occluded); },
      [](const std::string& path, std::span<const HitD> hits) { write_hits_d(path, hits); });

  nlohmann::json summary = trace_summary({
      .accel = accel->spec(),
      .scene = name,
      .primitives = scene.triangle_count(),
      .rays = rays.size(),
      .query = args.occlusion ? "occluded" : "intersect",
      .trace_ms = passes.trace_ms,
      .hit_count = passes.hit_count,
      .memory_bytes = accel->memory_bytes(),
      .scene_memory_bytes = scene.memory_bytes(),
      .input_memory_bytes = scene.memory_bytes(),
  });
  summary["precision"] = "double";
  summary["build_ms_median"] = median(build_ms);
  summary["build_ms"] = build_ms;
  if (!args.offset.empty()) summary["offset"] = {offset.x, offset.y, offset.z};
  if (!args.out.empty()) summary["out"] = args.out;
  fmt::print("{}\n", summary.dump());
  return 0;
}

}  // namespace rayaccel::cli
