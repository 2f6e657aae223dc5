// Ray/AABB slab test, conservative in floating point (Ize 2013, "Robust BVH Ray Traversal"): both slab distances
// are widened by 2*gamma(3) so rounding never turns a hit into a miss; +-0 direction components and rays lying in a
// face plane are handled without special cases, and void (NaN) rays never hit.
#pragma once

#include <limits>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/float_rounding.h"
#include "rayaccel/core/ray.h"

namespace rayaccel {

/// Relative rounding bound of three float operations, gamma(3) = 3u/(1-3u) with u = 2^-24 (Pharr et al., pbrt).
inline constexpr float kGamma3 = float_gamma(3);
/// Multipliers that move a distance away from zero (far bound) or toward zero by 2*gamma(3).
inline constexpr float kSlabWidenUp = 1.0f + 2.0f * kGamma3;
inline constexpr float kSlabWidenDown = 1.0f - 2.0f * kGamma3;

/// Clips [t_near, t_far] to the box. Returns false (and leaves garbage in t_near/t_far) when the clipped interval is
/// empty. Conservative: a ray that touches the closed box in exact arithmetic is never rejected. NaN slab distances
/// (ray parallel to and lying in a face plane) constrain nothing, so such rays count as touching.
inline bool clip_ray_to_box(const PreparedRay& r, const AABB& box, float& t_near, float& t_far) {
  for (int a = 0; a < 3; ++a) {
    const float near_plane = r.negative[a] ? box.hi[a] : box.lo[a];
    const float far_plane = r.negative[a] ? box.lo[a] : box.hi[a];
    float t0 = (near_plane - r.origin[a]) * r.inv_direction[a];
    float t1 = (far_plane - r.origin[a]) * r.inv_direction[a];
    // Widen both ends (near toward -inf, far toward +inf) so a box is never rejected against the current closest
    // hit because of rounding in its own entry distance.
    t0 *= t0 >= 0.0f ? kSlabWidenDown : kSlabWidenUp;
    t1 *= t1 >= 0.0f ? kSlabWidenUp : kSlabWidenDown;
    // Written as "candidate beats current ? candidate : current" so a NaN candidate leaves the interval alone.
    t_near = t0 > t_near ? t0 : t_near;
    t_far = t1 < t_far ? t1 : t_far;
  }
  return t_near <= t_far;
}

/// True when the ray's segment [t_min, t_max] touches the box; *t_entry receives the entry distance (for
/// near-first ordering) when given.
inline bool intersect_box(const PreparedRay& r, const AABB& box, float t_min, float t_max, float* t_entry = nullptr) {
  float t_near = t_min, t_far = t_max;
  const bool hit = clip_ray_to_box(r, box, t_near, t_far);
  if (t_entry) *t_entry = t_near;
  return hit;
}

}  // namespace rayaccel
