// k-DOP (discrete oriented polytope) as a BVH volume, k = 14, 18, 26: k/2 slabs on the fixed directions of
// geometry/ray_kdop.h (Klosowski et al. 1998). Fit: per-slab min/max projections; surface area and volume: exact, by
// clipping each face plane against all other half-spaces.
#pragma once

#include <span>

#include "rayaccel/bv/bounding_volume.h"
#include "rayaccel/geometry/ray_kdop.h"

namespace rayaccel {

template <int K>
constexpr const char* kdop_name() {
  if constexpr (K == 14) return "kdop14";
  else if constexpr (K == 18) return "kdop18";
  else return "kdop26";
}

template <int K>
struct KdopVolume {
  static constexpr const char* kName = kdop_name<K>();
  static constexpr int kSlabs = K / 2;
  using RayContext = KdopRay<K>;

  // The k-DOP is {p : lo[j] <= dot(kdop_directions<K>()[j], p) <= hi[j]}; empty while lo > hi.
  float lo[kSlabs];  ///< 4 * k/2 bytes
  float hi[kSlabs];  ///< 4 * k/2 bytes

  KdopVolume();
  static RayContext prepare(const PreparedRay& ray) { return RayContext(ray); }
  /// Encloses every point (projections rounded outward, plus a margin of a few float ulps of the largest
  /// coordinate); empty span -> empty k-DOP.
  static KdopVolume fit(std::span<const Vec3> points);

  bool intersect(const RayContext& c, float t_min, float t_max, float* t_entry) const {
    return intersect_kdop<K>(c, lo, hi, t_min, t_max, t_entry);
  }
  bool is_empty() const;
  /// Exact polytope area (double-sided for a flat k-DOP, like AABB::surface_area). Clips k face polygons against k-1
  /// half-spaces each: microseconds, meant for reports rather than inner build loops.
  float surface_area() const;
  float volume() const;
  /// The box of the three axis slabs.
  AABB bounds() const;
  /// Within every slab, in double with a tolerance of a few float ulps.
  bool contains(const Vec3& p) const;
};

using Kdop14Volume = KdopVolume<14>;
using Kdop18Volume = KdopVolume<18>;
using Kdop26Volume = KdopVolume<26>;
// fit, surface_area, volume, bounds, contains and the constructor are defined in src/bv/kdop_volume.cpp and
// instantiated there for k = 14, 18, 26; no extern-template declaration, so intersect stays inlinable everywhere.
static_assert(BoundingVolume<Kdop14Volume>);
static_assert(BoundingVolume<Kdop18Volume>);
static_assert(BoundingVolume<Kdop26Volume>);

}  // namespace rayaccel
