// Ray/k-DOP test for the fixed direction sets of Klosowski et al. 1998 ("Efficient Collision Detection Using
// Bounding Volume Hierarchies of k-DOPs"): the ray is projected on every slab direction once per ray, then each node
// is a slab test over k/2 pairs, made conservative like the AABB test of ray_box.h (Ize 2013).
#pragma once

#include <array>
#include <cmath>
#include <limits>

#include "rayaccel/core/ray.h"
#include "rayaccel/core/float_rounding.h"
#include "rayaccel/geometry/slab_interval.h"

namespace rayaccel {

/// The slab directions of a k-DOP (k = 14, 18, 26), unnormalized with components in {-1, 0, 1}: first the three
/// coordinate axes, then for 14 and 26 the four corner diagonals, then for 18 and 26 the six edge diagonals.
template <int K>
constexpr std::array<Vec3, K / 2> kdop_directions() {
  static_assert(K == 14 || K == 18 || K == 26, "k-DOPs exist for k = 14, 18, 26");
  constexpr Vec3 corners[4] = {{1, 1, 1}, {1, 1, -1}, {1, -1, 1}, {-1, 1, 1}};
  constexpr Vec3 edges[6] = {{1, 1, 0}, {1, -1, 0}, {1, 0, 1}, {1, 0, -1}, {0, 1, 1}, {0, 1, -1}};
  std::array<Vec3, K / 2> dirs{};
  int n = 0;
  dirs[n++] = {1, 0, 0};
  dirs[n++] = {0, 1, 0};
  dirs[n++] = {0, 0, 1};
  if constexpr (K != 18) for (const Vec3& c : corners) dirs[n++] = c;
  if constexpr (K != 14) for (const Vec3& e : edges) dirs[n++] = e;
  return dirs;
}

/// dot(direction, p) in double. Every direction component is -1, 0 or 1, so only the two additions round, each by
/// 2^-53 relative: far below float resolution (the fitted volumes carry a margin of several float ulps).
inline double kdop_project(const Vec3& direction, const Vec3& p) {
  return double(direction.x) * p.x + double(direction.y) * p.y + double(direction.z) * p.z;
}

/// A ray projected on the k/2 slab directions, made once per ray. The projected origin is moved toward the slab
/// interior on each side (origin_lo up, origin_hi down) by kRayOriginSlack of |origin|_1 and rounded in the same
/// direction, and the reciprocal direction is correctly rounded, so each slab distance carries at most three
/// roundings, as in the AABB test.
template <int K>
struct KdopRay {
  static constexpr int kSlabs = K / 2;
  float origin_lo[kSlabs];  ///< projected origin rounded up: used with the lo planes
  float origin_hi[kSlabs];  ///< projected origin rounded down: used with the hi planes
  float inv_direction[kSlabs];
  bool negative[kSlabs];  ///< sign bit of the projected direction (kept for +-0)

  explicit KdopRay(const PreparedRay& r) {
    constexpr auto dirs = kdop_directions<K>();
    const double slack =
        kRayOriginSlack * (double(std::fabs(r.origin.x)) + std::fabs(r.origin.y) + std::fabs(r.origin.z));
    for (int j = 0; j < kSlabs; ++j) {
      const double o = kdop_project(dirs[j], r.origin);
      const double d = kdop_project(dirs[j], r.direction);
      origin_lo[j] = round_up_to_float(o + slack);
      origin_hi[j] = round_down_to_float(o - slack);
      // For one axis d equals a float component and keeps its sign of zero; a diagonal sum of zero is +0.
      inv_direction[j] = static_cast<float>(1.0 / d);
      negative[j] = std::signbit(inv_direction[j]);
    }
  }
};

/// (plane - origin) * inv_direction, the distance to a slab plane. A diagonal projection reaches up to three times
/// FLT_MAX, so for finite points and origins the float difference can overflow where the distance itself is finite
/// (a plane at -3e38 seen from a projected origin at 5e37, with |inv_direction| < 1): the rare infinite difference is
/// then recomputed in double, where it is exact up to a relative 2^-53, far inside the widening's budget. An infinite
/// plane (a projection beyond float's range, rounded outward by the fit) stays infinite.
inline float kdop_slab_distance(float plane, float origin, float inv_direction) {
  const float difference = plane - origin;
  if (!std::isinf(difference)) [[likely]] return difference * inv_direction;
  return static_cast<float>((double(plane) - double(origin)) * double(inv_direction));
}

/// True when the segment [t_min, t_max] touches the k-DOP {p : lo[j] <= dot(dir[j], p) <= hi[j]}; *t_entry gets the
/// entry distance. Conservative like intersect_box: never rejects a ray that touches the closed k-DOP in exact
/// arithmetic; a ray lying in a slab plane is not constrained by that slab; void rays and empty k-DOPs (lo > hi)
/// never hit.
template <int K>
inline bool intersect_kdop(const KdopRay<K>& r, const float* lo, const float* hi, float t_min, float t_max,
                           float* t_entry = nullptr) {
  // The farthest entry and nearest exit over all slabs; widening these once is the same as widening every slab
  // distance (the widening is monotone) and cheaper.
  float enter = -std::numeric_limits<float>::infinity(), leave = std::numeric_limits<float>::infinity();
  for (int j = 0; j < KdopRay<K>::kSlabs; ++j) {
    const float t_lo = kdop_slab_distance(lo[j], r.origin_lo[j], r.inv_direction[j]);
    const float t_hi = kdop_slab_distance(hi[j], r.origin_hi[j], r.inv_direction[j]);
    const float t0 = r.negative[j] ? t_hi : t_lo;
    const float t1 = r.negative[j] ? t_lo : t_hi;
    // "Candidate beats current ? candidate : current", so a NaN slab distance (ray in a slab plane) is ignored.
    enter = t0 > enter ? t0 : enter;
    leave = t1 < leave ? t1 : leave;
  }
  return clip_to_widened_slabs(enter, leave, t_min, t_max, t_entry);
}

}  // namespace rayaccel
