// The BoundingVolume concept every BVH node volume satisfies (AABB, sphere, OBB, k-DOP, capped hull, capsule):
// fitted to the hull points of a node's primitives, tested against a ray conservatively (never misses a ray that
// hits the contents), and measured by surface area for SAH and tightness reports.
#pragma once

#include <concepts>
#include <span>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/ray.h"

namespace rayaccel {

template <class BV>
concept BoundingVolume = requires(const BV bv, std::span<const Vec3> points, const PreparedRay& ray,
                                  const typename BV::RayContext& context, float t) {
  /// Per-ray constants of this volume's test (e.g. the ray projected on k-DOP axes), made once per ray.
  { BV::prepare(ray) } -> std::same_as<typename BV::RayContext>;
  /// A volume enclosing every point; for an empty span, a volume no ray hits.
  { BV::fit(points) } -> std::same_as<BV>;
  /// True when the ray's [t_min, t_max] touches the volume; the entry distance goes to *t_entry.
  { bv.intersect(context, t, t, &t) } -> std::same_as<bool>;
  { bv.surface_area() } -> std::convertible_to<float>;
  /// An axis-aligned box enclosing the volume.
  { bv.bounds() } -> std::same_as<AABB>;
  /// True when the point lies inside (within rounding) — used by validate().
  { bv.contains(ray.origin) } -> std::same_as<bool>;
  /// Short name used in registry specs: "aabb", "sphere", "obb", "kdop14", "kdop18", "kdop26", "hull", "capsule".
  { BV::kName } -> std::convertible_to<const char*>;
};

}  // namespace rayaccel
