// Ray/AABB slab test, conservative in floating point (Ize 2013, "Robust BVH Ray Traversal"): both slab distances
// are widened by 2*gamma(3) so rounding never turns a hit into a miss; +-0 direction components and rays lying in a
// face plane are handled without special cases, and void (NaN) rays never hit.
#pragma once

#include <limits>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/float_rounding.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/geometry/slab.h"

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
    clip_slab(box.lo[a], box.hi[a], r.origin[a], r.inv_direction[a], r.negative[a], kSlabWidenDown, kSlabWidenUp,
              t_near, t_far);
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
