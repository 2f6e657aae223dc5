// Axis-aligned box as a BVH bounding volume: the robust slab test of geometry/ray_box.h (Ize 2013).
#pragma once

#include <span>

#include "rayaccel/bv/bounding_volume.h"
#include "rayaccel/geometry/ray_box.h"

namespace rayaccel {

struct AabbVolume {
  static constexpr const char* kName = "aabb";
  struct RayContext {
    const PreparedRay* ray;
  };
  AABB box;

  static RayContext prepare(const PreparedRay& ray) { return {&ray}; }
  static AabbVolume fit(std::span<const Vec3> points) {
    AabbVolume v;
    for (const Vec3& p : points) v.box.extend(p);
    return v;
  }
  bool intersect(const RayContext& c, float t_min, float t_max, float* t_entry) const {
    return intersect_box(*c.ray, box, t_min, t_max, t_entry);
  }
  float surface_area() const { return box.surface_area(); }
  AABB bounds() const { return box; }
  bool contains(const Vec3& p) const { return box.contains(p); }
};
static_assert(BoundingVolume<AabbVolume>);

}  // namespace rayaccel
