// A double ray against a float box stored relative to a double anchor point, conservative in double (Ize 2013,
// "Robust BVH Ray Traversal", with u = 2^-53): far boxes keep float's resolution near their anchor.
#pragma once

#include <cmath>
#include <limits>
#include <span>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/float_rounding.h"
#include "rayaccel/core/ray_d.h"
#include "rayaccel/geometry/slab.h"

namespace rayaccel {

/// Slab distances widened by 2 gamma(6): the rounding of the pushed plane, the difference, the reciprocal and the
/// product (the plane push and the anchor: docs/design.md).
inline constexpr double kSlabWidenUpD = 1.0 + 2.0 * double_gamma(6);
inline constexpr double kSlabWidenDownD = 1.0 - 2.0 * double_gamma(6);

/// The ray's origin in a box frame (o - anchor, rounded) and the slack that pushes each face plane outward.
struct BoxFrameD {
  DVec3 origin;
  DVec3 slack;
  BoxFrameD(const PreparedRayD& r, const DVec3& anchor) : origin(r.origin - anchor) {
    for (int a = 0; a < 3; ++a) slack[a] = 0x1p-50 * std::fabs(origin[a]);
  }
};

/// True when the segment [t_min, t_max] of the ray touches `box` (relative to the frame's anchor); *t_entry receives
/// the entry distance.
inline bool intersect_box(const PreparedRayD& r, const BoxFrameD& frame, const AABB& box, double t_min, double t_max,
                          double* t_entry) {
  double t_near = t_min, t_far = t_max;
  for (int a = 0; a < 3; ++a) {
    const double lo = double(box.lo[a]) - frame.slack[a], hi = double(box.hi[a]) + frame.slack[a];
    clip_slab(lo, hi, frame.origin[a], r.inv_direction[a], r.negative[a], kSlabWidenDownD, kSlabWidenUpD, t_near,
              t_far);
  }
  *t_entry = t_near;
  return t_near <= t_far;
}

/// The smallest float box that contains the exact points p - anchor (p and anchor in the double domain): each
/// difference is computed in double with its exact rounding error (Knuth's two-sum), stepped one double outward when
/// it was rounded inward, and rounded outward to float.
inline AABB anchored_float_box(std::span<const DVec3> points, const DVec3& anchor) {
  AABB box;
  for (const DVec3& p : points) {
    Vec3 lo, hi;
    for (int a = 0; a < 3; ++a) {
      const double b = -anchor[a];
      const double x = p[a] + b;
      const double b_virtual = x - p[a];
      const double error = (p[a] - (x - b_virtual)) + (b - b_virtual);  // exact: p - anchor == x + error
      const double below = error < 0.0 ? std::nextafter(x, -std::numeric_limits<double>::infinity()) : x;
      const double above = error > 0.0 ? std::nextafter(x, std::numeric_limits<double>::infinity()) : x;
      lo[a] = round_down_to_float(below);
      hi[a] = round_up_to_float(above);
    }
    box.extend(AABB(lo, hi));
  }
  return box;
}

}  // namespace rayaccel
