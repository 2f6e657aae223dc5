// A double ray against a float box, conservative in double (Ize 2013, "Robust BVH Ray Traversal", with u = 2^-53):
// the box's float bounds are exact in double, and both slab distances are widened by 2*gamma(3), so rounding never
// turns a ray that touches the closed box into a miss. NaN slab distances (a ray parallel to and lying in a face
// plane) constrain nothing, and void rays (empty interval) never hit, as in ray_box.h.
#pragma once

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/ray_d.h"

namespace rayaccel {

inline constexpr double kSlabWidenUpD = 1.0 + 2.0 * double_gamma(3);
inline constexpr double kSlabWidenDownD = 1.0 - 2.0 * double_gamma(3);

/// True when the segment [t_min, t_max] of the ray touches the box; *t_entry receives the entry distance.
inline bool intersect_box(const PreparedRayD& r, const AABB& box, double t_min, double t_max, double* t_entry) {
  double t_near = t_min, t_far = t_max;
  for (int a = 0; a < 3; ++a) {
    const double near_plane = r.negative[a] ? box.hi[a] : box.lo[a];
    const double far_plane = r.negative[a] ? box.lo[a] : box.hi[a];
    double t0 = (near_plane - r.origin[a]) * r.inv_direction[a];
    double t1 = (far_plane - r.origin[a]) * r.inv_direction[a];
    t0 *= t0 >= 0.0 ? kSlabWidenDownD : kSlabWidenUpD;
    t1 *= t1 >= 0.0 ? kSlabWidenUpD : kSlabWidenDownD;
    t_near = t0 > t_near ? t0 : t_near;
    t_far = t1 < t_far ? t1 : t_far;
  }
  *t_entry = t_near;
  return t_near <= t_far;
}

}  // namespace rayaccel
