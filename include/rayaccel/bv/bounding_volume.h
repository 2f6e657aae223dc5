// The BoundingVolume concept every BVH node volume satisfies (AABB, sphere, OBB, k-DOP): fitted to the hull
// points of a node's primitives, tested against a prepared ray conservatively (never misses a ray that hits the
// contents), and measured by surface area for SAH and tightness reports.
#pragma once

#include <concepts>
#include <span>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/ray.h"

namespace rayaccel {

template <class BV>
concept BoundingVolume = requires(const BV bv, std::span<const Vec3> points, const PreparedRay& ray, float t) {
  /// A volume enclosing every point (for an empty span: a volume no ray hits).
  { BV::fit(points) } -> std::same_as<BV>;
  /// True when [t_min, t_max] of the ray touches the volume; the entry distance goes to *t_entry.
  { bv.intersect(ray, t, t, &t) } -> std::same_as<bool>;
  { bv.surface_area() } -> std::convertible_to<float>;
  /// An axis-aligned box enclosing the volume.
  { bv.bounds() } -> std::same_as<AABB>;
  /// Short name used in registry specs ("aabb", "sphere", "obb", "kdop14", ...).
  { BV::kName } -> std::convertible_to<const char*>;
};

}  // namespace rayaccel
