// Batch splitting shared by every accelerator; the queries beyond the first hit, insertion, removal, saving and
// loading where a structure has none.
#include "rayaccel/accel/accelerator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <string>

#include "rayaccel/core/error.h"

namespace rayaccel {

namespace {
[[noreturn]] void unsupported(const Accelerator& accel, const char* query) {
  throw Error(std::string(query) + " queries are not supported by '" + accel.spec() +
              "' (supported by brute_force, bvh and bvh_wide: their traversals enumerate every candidate)");
}

/// The name of a structure in an error message: its spec, or its kind when it was made without the registry.
std::string structure_name(const Accelerator& accel) {
  return accel.spec().empty() ? std::string("this structure") : "'" + accel.spec() + "'";
}

[[noreturn]] void lacks(const Accelerator& accel, const std::string& what, const char* which) {
  throw Error(what + ": " + structure_name(accel) + " does not support it (" + which + ")");
}
}  // namespace

const char* to_string(UpdateKind kind) { return kind == UpdateKind::refitted ? "refitted" : "rebuilt"; }

void Accelerator::insert(std::uint32_t prim_id) {
  lacks(*this, "insert(" + std::to_string(prim_id) + ")", "insertion and removal: octree; the others rebuild");
}
void Accelerator::remove(std::uint32_t prim_id) {
  lacks(*this, "remove(" + std::to_string(prim_id) + ")", "insertion and removal: octree; the others rebuild");
}
void Accelerator::save(const std::filesystem::path& path) const {
  lacks(*this, "save to '" + path.string() + "'", "saved structures: bvh (every volume) and bvh_wide");
}
void Accelerator::load(const std::filesystem::path& path, const Scene&) {
  lacks(*this, "load from '" + path.string() + "'", "saved structures: bvh (every volume) and bvh_wide");
}

Hit Accelerator::intersect(const QueryContext&, const Ray&, std::size_t) const { detail::refuse_context(*this); }
bool Accelerator::occluded(const QueryContext&, const Ray&, std::size_t) const { detail::refuse_context(*this); }
void Accelerator::intersect(const QueryContext&, std::span<const Ray>, std::span<Hit>) const {
  detail::refuse_context(*this);
}
void Accelerator::occluded(const QueryContext&, std::span<const Ray>, std::span<std::uint8_t>) const {
  detail::refuse_context(*this);
}

std::size_t Accelerator::all_hits(const Ray&, std::vector<Hit>&, std::size_t) const { unsupported(*this, "all-hits"); }
std::size_t Accelerator::count_hits(const Ray&) const { unsupported(*this, "hit-count"); }
ClosestPoint Accelerator::closest_point(const Vec3&, float) const { unsupported(*this, "closest-point"); }

void Accelerator::count_hits(std::span<const Ray> rays, std::span<std::uint32_t> counts) const {
  detail::check_batch_sizes(rays.size(), counts.size(), 0);
  if (!supports_queries()) unsupported(*this, "hit-count");
  detail::parallel_for_rays(rays.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) counts[i] = static_cast<std::uint32_t>(count_hits(rays[i]));
  });
}

void Accelerator::closest_points(std::span<const Vec3> points, std::span<ClosestPoint> out, float max_distance) const {
  detail::check_batch_sizes(points.size(), out.size(), 0);
  if (!supports_queries()) unsupported(*this, "closest-point");
  for (std::size_t i = 0; i < points.size(); ++i) {
    try {
      detail::check_point_query(points[i], max_distance);
    } catch (const Error& e) {
      throw Error(std::string(e.what()) + " (point " + std::to_string(i) + " of the batch)");
    }
  }
  detail::parallel_for_rays(points.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) out[i] = closest_point(points[i], max_distance);
  });
}

}  // namespace rayaccel

namespace rayaccel::detail {

void check_point_query(const Vec3& point, float max_distance) {
  if (!is_finite(point)) {
    std::ostringstream text;
    text << "closest point: the query point (" << point.x << ", " << point.y << ", " << point.z
         << ") is not finite";
    throw Error(text.str());
  }
  if (!(max_distance >= 0.0f)) {
    throw Error("closest point: max_distance " + std::to_string(max_distance) + " must be >= 0 (and not NaN)");
  }
}

bool refit_covers_scene(const Scene& scene, std::span<const std::uint32_t> ids) {
  std::vector<std::uint8_t> held(scene.primitive_count(), 0);
  for (const std::uint32_t id : ids) {
    if (id >= held.size()) return false;
    held[id] = 1;
  }
  for (std::uint32_t id = 0; id < scene.primitive_count(); ++id) {
    if (!held[id] && scene.is_valid(id)) return false;
  }
  return true;
}

void require_triangle_scene(const Scene& scene, const char* query) {
  if (scene.kind() != PrimitiveKind::triangles) {
    throw Error(std::string(query) + " queries need a triangle scene; '" + scene.name() + "' holds " +
                to_string(scene.kind()));
  }
}

void parallel_for_rays(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
  constexpr std::size_t kGrain = 64;  // rays per task: enough to hide scheduling, small enough to balance
  // Rays are traced in the caller's floating-point environment (MXCSR: rounding, flush-to-zero, denormals-are-zero),
  // as a loop on the calling thread would be. Without a context that captures it, TBB tasks run with the settings
  // its default context captured when TBB was first used, which may be another library's: Embree's build leaves
  // FTZ/DAZ there, and with DAZ a ray origin 2^-149 above a floor reads as lying on it.
  tbb::task_group_context context(tbb::task_group_context::bound,
                                  tbb::task_group_context::default_traits | tbb::task_group_context::fp_settings);
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, count, kGrain),
      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); }, context);
}

void parallel_for_packets(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
  parallel_for_rays((count + kPacketSize - 1) / kPacketSize, [&](std::size_t begin, std::size_t end) {
    body(begin * kPacketSize, std::min(end * kPacketSize, count));
  });
}

namespace {
/// The context's per-ray arrays with their names, for the checks below.
struct PerRayArray {
  const char* name;
  std::size_t size;
};
std::array<PerRayArray, 3> per_ray_arrays(const QueryContext& context) {
  return {{{"skip_primitive", context.skip_primitive.size()},
           {"skip_geometry", context.skip_geometry.size()},
           {"ray_mask", context.ray_mask.size()}}};
}
}  // namespace

void check_context_sizes(const QueryContext& context, std::size_t rays) {
  for (const PerRayArray& a : per_ray_arrays(context)) {
    if (a.size != 0 && a.size != rays) {
      throw Error("query context: " + std::string(a.name) + " has " + std::to_string(a.size) + " entries for " +
                  std::to_string(rays) + " rays (one per ray, or none)");
    }
  }
}

void check_context_index(const QueryContext& context, std::size_t ray_index) {
  for (const PerRayArray& a : per_ray_arrays(context)) {
    if (a.size != 0 && a.size <= ray_index) {
      throw Error("query context: " + std::string(a.name) + " has " + std::to_string(a.size) +
                  " entries, none for ray index " + std::to_string(ray_index));
    }
  }
}

void refuse_context(const Accelerator& accel) {
  throw Error("query contexts (skip, masks, filters): " + structure_name(accel) +
              " does not support them; every rayaccel structure does");
}

void check_batch_sizes(std::size_t rays, std::size_t outputs, std::size_t stats) {
  if (outputs != rays) {
    throw Error("batch: " + std::to_string(rays) + " rays but " + std::to_string(outputs) + " output slots");
  }
  if (stats != 0 && stats != rays) {
    throw Error("batch: " + std::to_string(rays) + " rays but " + std::to_string(stats) + " statistics records");
  }
}

}  // namespace rayaccel::detail
