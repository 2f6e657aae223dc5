// One axis of the conservative ray/box slab test (Ize 2013, "Robust BVH Ray Traversal"), the one copy that the float
// box test (ray_box.h) and the double one (ray_box_d.h) share.
#pragma once

namespace rayaccel {

/// Clips [t_near, t_far] to the slab between the planes `lo` and `hi` of one axis, for a ray with coordinate
/// `origin`, reciprocal direction `inv` and `negative` set when it points down the axis. Both slab distances are
/// scaled away from the interval (near toward -inf, far toward +inf) by `widen_down` < 1 < `widen_up`, so rounding
/// never rejects a box the ray touches; written as "candidate beats current ? candidate : current" so a NaN distance
/// (a ray lying in a face plane) constrains nothing.
template <class Real>
inline void clip_slab(Real lo, Real hi, Real origin, Real inv, int negative, Real widen_down, Real widen_up,
                      Real& t_near, Real& t_far) {
  const Real near_plane = negative ? hi : lo;
  const Real far_plane = negative ? lo : hi;
  Real t0 = (near_plane - origin) * inv;
  Real t1 = (far_plane - origin) * inv;
  t0 *= t0 >= Real(0) ? widen_down : widen_up;
  t1 *= t1 >= Real(0) ? widen_up : widen_down;
  t_near = t0 > t_near ? t0 : t_near;
  t_far = t1 < t_far ? t1 : t_far;
}

}  // namespace rayaccel
