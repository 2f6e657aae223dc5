// Capped convex hull as a BVH volume: the points' box cut by at most kMaxPlanes Quickhull planes (Barber et al. 1996)
// moved out to the points' support, so it encloses them for any choice. Ray test: geometry/ray_hull.h.
#pragma once

#include <cstdint>
#include <span>

#include "rayaccel/bv/bounding_volume.h"
#include "rayaccel/geometry/ray_hull.h"

namespace rayaccel {

struct HullVolume {
  static constexpr const char* kName = "hull";
  /// Most hull planes beyond the box's six. Eight are two SSE lane sets, keep a node within three cache lines
  /// (164 bytes) and already take every face of a one- or two-triangle leaf (two sides and three or four edges);
  /// BENCHMARKS.md has the tightness each plane buys.
  static constexpr int kMaxPlanes = HullPlanes::kCount;
  struct RayContext {
    const PreparedRay* ray;
  };

  AABB box;                       ///<  24 bytes: the points' box (empty: the empty hull)
  std::uint32_t plane_count = 0;  ///<   4 bytes
  HullPlanes planes;              ///< 128 bytes: the first plane_count lanes are used, the others constrain nothing

  HullVolume();
  static RayContext prepare(const PreparedRay& ray) { return {&ray}; }
  /// Encloses every point exactly (offsets computed in double for the stored float normals and rounded up); the
  /// ray test's slack, not a fit margin, absorbs rounding. Empty span -> empty hull.
  static HullVolume fit(std::span<const Vec3> points) { return fit(points, kMaxPlanes); }
  /// The same with at most max_planes (<= kMaxPlanes) planes: for measuring what each plane buys.
  static HullVolume fit(std::span<const Vec3> points, int max_planes);

  bool intersect(const RayContext& c, float t_min, float t_max, float* t_entry) const {
    return intersect_hull(*c.ray, box, planes, t_min, t_max, t_entry);
  }
  bool is_empty() const { return box.is_empty(); }
  /// Exact polytope area (double-sided when flat, like AABB::surface_area): each face clipped by every other
  /// half-space. Microseconds, meant for reports rather than inner build loops.
  float surface_area() const;
  AABB bounds() const { return box; }
  /// Inside the box and every plane, in double with a tolerance of a few float ulps.
  bool contains(const Vec3& p) const;
};
static_assert(BoundingVolume<HullVolume>);

}  // namespace rayaccel
