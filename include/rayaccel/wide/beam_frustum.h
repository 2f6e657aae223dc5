// A beam's frustum in float for SIMD culling of wide-BVH children (Reshetov, Soupikov & Hurley 2005; Wald et al. 2006,
// frustum culling): planes through the apex that every ray of the beam is proven to lie on, with a stated margin.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/core/vec3.h"
#include "rayaccel/simd/lane_set.h"
#include "rayaccel/wide/wide_node.h"

namespace rayaccel::wide {

/// Planes through the apex a with normals n_p (floats): a box is culled when, for some p, every point x of the box
/// (grown by its slack) has n_p . (x - a) < 0, while every ray of the beam has n_p . d >= 0 and t >= 0 (holds()), so
/// no ray point lies in the box. The side planes come from the beam's four corner rays; axis planes (normal +-e_k)
/// are added where every corner and pixel ray points one way along axis k (the box faces of the beam's test).
///
/// Margin (frustum_cull_lanes()): the float value v = fl(n . fl(c - a)) of the box corner c farthest along n differs
/// from the exact n . (c - a) by at most gamma(4) * sum_k |n_k| |fl(c_k - a_k)| (one rounding of each difference, a
/// three-term dot product; gamma(4) < 2.4e-7) plus 4 * 2^-150 where products underflow. The test culls only when
/// fl(v + B) < 0 with B = fl(fl(2^-20 * sum_k |n_k|, rounded up) * max_k |fl(c_k - a_k)|) + 2^-126 >= 3.9 * that bound,
/// so the exact value is negative: a box the beam touches is never culled (tests/generalized/beam_frustum_test.cpp).
/// Slack: each box is first grown by 2^-16 of the largest magnitude among its coordinates and the apex's (so by at
/// least 0.99 of that after rounding): covers boxes a single ray's slab test enters although the exact ray misses
/// them by rounding, whose size grows with the distance from the origin (far apexes included).
struct BeamFrustum {
  static constexpr int kMaxPlanes = 7;  ///< four sides and three axis planes
  static constexpr float kMarginScale = 0x1p-20f;
  static constexpr float kSlackScale = 0x1p-16f;
  Vec3 apex;
  float apex_magnitude = 0.0f;   ///< max_k |apex_k|
  int plane_count = 0;           ///< 0: an invalid frustum (it holds no ray, culls nothing)
  float normal[kMaxPlanes][3]{};  ///< float normals (the planes themselves, not roundings of others)
  float margin[kMaxPlanes]{};     ///< 2^-20 * sum_k |normal_k|, rounded up
  bool far_is_hi[kMaxPlanes][3]{};  ///< normal_k >= 0: the box's hi face is farthest along the normal

  /// The frustum of the rays through `corners` (four directions in order around the beam's cross-section) from
  /// `apex`, with the axis planes where every corner points one way. Invalid when a value is not finite.
  static BeamFrustum through(const Vec3& apex, const Vec3 corners[4]);
  /// True when the ray starts at the apex, has t_min >= 0 and n_p . d > 0 proven for every plane (in double: the
  /// products of floats are exact, the two sums' rounding far below the 2^-50 relative margin required), so every
  /// point of the ray lies on the inner side of every plane.
  bool holds(const Ray& ray) const;
  bool valid() const { return plane_count > 0; }
  /// True when no ray the frustum holds can meet `box` (grown by its slack), by the test of frustum_child_lanes()
  /// for one box, the planes in four SSE lanes at a time: the same float operations for each box and plane, so the
  /// same margin. An empty box is outside. For structures whose nodes are tested one box at a time.
  bool box_outside(const AABB& box) const;
};

RAYACCEL_LANE_CODE_BEGIN
/// The lanes (children) of a W-wide node whose box the frustum may meet: non-empty children not culled by any plane
/// (see BeamFrustum for the margin and slack; slack_scale other than kSlackScale only to test the margin alone).
/// S::kWidth == W.
template <class S, int W>
RAYACCEL_LANE_INLINE int frustum_child_lanes(const BeamFrustum& f, const Node<W>& node,
                                             float slack_scale = BeamFrustum::kSlackScale) {
  static_assert(S::kWidth == W, "one lane a child");
  using F = typename S::F;
  const F sign_bit = S::set1(-0.0f);
  F lo[3], hi[3];
  F magnitude = S::set1(f.apex_magnitude);
  for (int k = 0; k < 3; ++k) {
    lo[k] = S::load(node.bounds[k][0]);
    hi[k] = S::load(node.bounds[k][1]);
    magnitude = S::max(magnitude, S::max(S::and_not(sign_bit, lo[k]), S::and_not(sign_bit, hi[k])));
  }
  const F nonempty = S::le(lo[0], hi[0]);  // an unused child has lo = +inf, hi = -inf
  const F slack = S::mul(magnitude, S::set1(slack_scale));
  F reach = S::zero();  // max_k |fl(c_k - a_k)| over both faces
  for (int k = 0; k < 3; ++k) {
    const F a = S::set1(f.apex[k]);
    lo[k] = S::sub(S::sub(lo[k], slack), a);
    hi[k] = S::sub(S::add(hi[k], slack), a);
    reach = S::max(reach, S::max(S::and_not(sign_bit, lo[k]), S::and_not(sign_bit, hi[k])));
  }
  F culled = S::zero();
  const F tiny = S::set1(0x1p-126f);
  for (int p = 0; p < f.plane_count; ++p) {
    const F* c[3];
    for (int k = 0; k < 3; ++k) c[k] = f.far_is_hi[p][k] ? &hi[k] : &lo[k];
    F v = S::mul(S::set1(f.normal[p][0]), *c[0]);
    v = S::add(v, S::mul(S::set1(f.normal[p][1]), *c[1]));
    v = S::add(v, S::mul(S::set1(f.normal[p][2]), *c[2]));
    const F bound = S::add(S::mul(S::set1(f.margin[p]), reach), tiny);
    culled = S::bit_or(culled, S::lt(S::add(v, bound), S::zero()));
  }
  return S::movemask(S::and_not(culled, nonempty));
}

/// The lanes of a set of rays, one a lane (origin, direction as PreparedRay reads it, t_min), that a float test
/// proves f.holds() for: origin equal to the apex, t_min >= 0 and, for every plane, v = fl(n . d) > fl(2^-20 * s) +
/// 2^-120 with s = sum_k |n_k d_k| in float. v is n . d within gamma(2) s + 3 * 2^-150 (a three-term float sum;
/// products that underflow), far inside that margin, so n . d > 2^-50 s holds exactly, as holds() asks. A sufficient
/// test: a lane it leaves out may still be held (holds() decides it). f must be valid().
template <class S>
RAYACCEL_LANE_INLINE int holds_in_lanes(const BeamFrustum& f, const typename S::F origin[3],
                                        const typename S::F direction[3], const typename S::F& t_min) {
  using F = typename S::F;
  const F sign_bit = S::set1(-0.0f);
  F held = S::ge(t_min, S::zero());
  for (int k = 0; k < 3; ++k) held = S::bit_and(held, S::eq(origin[k], S::set1(f.apex[k])));
  for (int p = 0; p < f.plane_count; ++p) {
    const F t0 = S::mul(S::set1(f.normal[p][0]), direction[0]);
    const F t1 = S::mul(S::set1(f.normal[p][1]), direction[1]);
    const F t2 = S::mul(S::set1(f.normal[p][2]), direction[2]);
    const F v = S::add(S::add(t0, t1), t2);
    const F scale = S::add(S::add(S::and_not(sign_bit, t0), S::and_not(sign_bit, t1)), S::and_not(sign_bit, t2));
    held = S::bit_and(held, S::gt(v, S::add(S::mul(scale, S::set1(0x1p-20f)), S::set1(0x1p-120f))));
  }
  return S::movemask(held);
}

/// holds_in_lanes() for rays[0 .. count), count <= S::kWidth, read from their records.
template <class S>
RAYACCEL_LANE_INLINE int holds_lanes(const BeamFrustum& f, const Ray* rays, int count) {
  using F = typename S::F;
  constexpr int W = S::kWidth;
  static_assert(sizeof(Ray) == 8 * sizeof(float), "Ray is the record ox oy oz t_min dx dy dz t_max");
  alignas(32) float field[7][W] = {};
  for (int i = 0; i < count; ++i) {
    float r[8];
    std::memcpy(r, &rays[i], sizeof(Ray));
    for (int k = 0; k < 7; ++k) field[k][i] = r[k];
  }
  const F sign_bit = S::set1(-0.0f);
  F origin[3], direction[3];
  for (int k = 0; k < 3; ++k) {
    origin[k] = S::load(field[k]);
    direction[k] = S::load(field[4 + k]);
    const F subnormal = S::lt(S::and_not(sign_bit, direction[k]), S::set1(0x1p-126f));  // read as zero of its sign
    direction[k] = S::and_not(S::and_not(sign_bit, subnormal), direction[k]);
  }
  return holds_in_lanes<S>(f, origin, direction, S::load(field[3])) & ((1 << count) - 1);
}
RAYACCEL_LANE_CODE_END

}  // namespace rayaccel::wide
