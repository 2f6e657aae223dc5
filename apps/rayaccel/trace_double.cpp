// `rayaccel trace SCENE RAYS --precision double`: the scene in double (a PLY file's coordinates as read, so `property
// double` keeps its 53 bits; other files and builtins through the float loader, exact in double), moved by --offset,
// a double structure (make_double_accelerator: brute_force or bvh with bv=aabb), .rays64 in, .hits64 or .occ out
// (scene/ray_io.h), and the float trace's summary line plus "precision":"double".
#include "trace_double.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "cli_common.h"
#include "trace_passes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/core/ray_d.h"
#include "rayaccel/double/double_accelerator.h"
#include "rayaccel/double/double_scene.h"
#include "rayaccel/scene/ply_reader.h"
#include "rayaccel/scene/ray_io.h"

namespace rayaccel::cli {

namespace {

constexpr int kBuilds = 3;

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

/// True when the file starts like a PLY file.
bool is_ply_file(const std::string& path) {
  std::array<std::byte, 5> head{};
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(head.data()), head.size());
  return looks_like_ply(std::span<const std::byte>(head.data(), static_cast<std::size_t>(in.gcount())));
}

/// The scene's mesh in double, every vertex moved by `offset`, and its name (the file's stem, or the builtin's).
TriangleMeshD load_double_mesh(const std::string& spec, const DVec3& offset, std::string& name) {
  check_scene_exists(spec);
  if (!is_builtin(spec) && is_ply_file(spec)) {
    TriangleMeshD mesh = read_ply_double(spec);
    if (mesh.triangles.empty()) throw Error("mesh file '" + spec + "' has no triangles");
    for (DVec3& v : mesh.vertices) v = v + offset;
    name = std::filesystem::path(spec).stem().string();
    return mesh;
  }
  const Scene scene = load_scene_checked(spec);
  if (scene.kind() != PrimitiveKind::triangles) {
    throw UsageError("--precision double: scene '" + spec + "' holds " + to_string(scene.kind()) +
                     "; the double path traces triangle meshes only");
  }
  name = scene.name();
  return to_double_mesh(scene.mesh(), offset);
}

}  // namespace

int run_trace_double(const TraceDoubleArgs& args) {
  const std::string spec = args.accel.empty() ? "bvh" : args.accel;
  check_double_spec(spec);
  const DVec3 offset = args.offset.empty() ? DVec3{} : parse_dvec3(args.offset, "--offset");
  if (!args.out.empty()) check_output_path(args.out, args.occlusion ? "occlusion file" : "hit file");

  std::string name;
  const DoubleScene scene(load_double_mesh(args.scene, offset, name));
  const std::vector<RayD> rays = read_rays_d(args.rays);

  std::vector<double> build_ms;
  std::unique_ptr<DoubleAccelerator> accel;
  for (int i = 0; i < kBuilds; ++i) {
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
