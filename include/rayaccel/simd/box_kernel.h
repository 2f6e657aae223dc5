// The robust slab test of one ray against the W child boxes of a node stored SoA (Ize 2013, "Robust BVH ray
// traversal"), written once over a lane set (Sse4: four children, Avx8: eight), with the origin shift that keeps
// rays from subnormal origin coordinates out of subnormal arithmetic.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "rayaccel/core/ray.h"
#include "rayaccel/geometry/ray_box.h"
#include "rayaccel/simd/lane_set.h"

namespace rayaccel::simd {

/// The origin the wide box tests use, and the slack that makes up for it. A ray leaving an exact point on a plane at
/// 0 (a floor at y = 0, say) starts a subnormal distance from it (pbrt-style origin offsets give 2^-149), and
/// (plane - origin) * 1/d then computes with subnormals at every node, which costs a microcode assist per operation
/// (BENCHMARKS.md, "Option choices", has what it cost). Such a coordinate (0 < |o| <
/// FLT_MIN, on an axis the ray is not parallel to) is replaced by 0 for the box tests only, which moves that axis's
/// slab distances by s = o/d exactly; the interval is then widened by slab_shift >= 4|s| (and at least FLT_MIN, so the
/// widening itself is normal arithmetic) on both ends, after the relative widening by the factors below, which are
/// 8u looser than kSlabWiden* so the rounding of those additions is covered too (the bound is worked out in
/// BoxKernel::intersect). Only for rays with t_min >= 0 (the box kernels' short path); other rays keep their origin.
struct BoxTestOrigin {
  Vec3 origin;
  float slab_shift = 0.0f;  ///< 0: the ray's own origin, nothing to add
  float widen_down = kSlabWidenDown;
  float widen_up = kSlabWidenUp;

  explicit BoxTestOrigin(const PreparedRay& r) : origin(r.origin) {
    if (!(r.t_min >= 0.0f)) return;
    constexpr float kMinNormal = std::numeric_limits<float>::min();
    float shift = 0.0f;
    bool moved = false;
    for (int a = 0; a < 3; ++a) {
      const float o = r.origin[a];
      if (o == 0.0f || !(std::fabs(o) < kMinNormal) || std::isinf(r.inv_direction[a])) continue;
      origin[a] = 0.0f;
      moved = true;
      // 4 |o / d| <= 4 * FLT_MIN * |1/d| (1 + u): bounded through FLT_MIN, as multiplying o itself would be a
      // subnormal operation too.
      shift = std::max(shift, 0x1p-123f * std::fabs(r.inv_direction[a]));
    }
    if (!moved) return;
    slab_shift = std::max(shift, kMinNormal);
    widen_down = kSlabWidenDown - 0x1p-21f;
    widen_up = kSlabWidenUp + 0x1p-21f;
  }
};

RAYACCEL_LANE_CODE_BEGIN
/// Per-ray constants of the box test over S's lanes (Sse4: four children, Avx8: eight), splatted once per ray. With
/// eight lanes, used only inside AVX2 functions (see RAYACCEL_LANE_INLINE).
template <class S>
struct BoxPacket {
  typename S::F origin[3];
  typename S::F inv_direction[3];
  typename S::F t_min;
  typename S::F widen_down, widen_up, slab_shift;  ///< see BoxTestOrigin
  /// Byte offsets of each axis's near and far planes in a node's `float bounds[3][2][S::kWidth]` (the near plane is
  /// lo where the direction is >= +0, hi where it is negative), worked out once per ray so a node test is six loads.
  std::ptrdiff_t near_bytes[3], far_bytes[3];
  bool t_min_non_negative;  ///< then every entry distance is >= 0 and the widening needs no per-lane sign test
  bool shifted;             ///< slab_shift != 0: the origin was moved off subnormal coordinates

  RAYACCEL_LANE_INLINE explicit BoxPacket(const PreparedRay& r) {
    const BoxTestOrigin box_origin(r);
    for (int a = 0; a < 3; ++a) {
      origin[a] = S::set1(box_origin.origin[a]);
      inv_direction[a] = S::set1(r.inv_direction[a]);
      constexpr auto kPlaneBytes = static_cast<std::ptrdiff_t>(S::kWidth * sizeof(float));
      near_bytes[a] = (2 * a + (r.negative[a] ? 1 : 0)) * kPlaneBytes;
      far_bytes[a] = (2 * a + (r.negative[a] ? 0 : 1)) * kPlaneBytes;
    }
    t_min = S::set1(r.t_min);
    widen_down = S::set1(box_origin.widen_down);
    widen_up = S::set1(box_origin.widen_up);
    slab_shift = S::set1(box_origin.slab_shift);
    t_min_non_negative = r.t_min >= 0.0f;
    shifted = box_origin.slab_shift != 0.0f;
  }
};

/// One ray against the S::kWidth child boxes of a node (robust slab test, Ize 2013), in the form the width-generic
/// traversal calls: returns the lane mask of the boxes whose clipped interval meets [t_min, t_far], entry distances
/// to t_entry. max/min return their second operand when either is NaN, so the running bound goes second and a NaN
/// slab distance (ray in a face plane) constrains nothing, as in clip_ray_to_box().
template <class S>
struct BoxKernel {
  static constexpr int kWidth = S::kWidth;
  using Lanes = S;  ///< lanes of the leaf test used with this node width
  using Packet = BoxPacket<S>;
  using F = typename S::F;

  RAYACCEL_LANE_INLINE static Packet prepare(const PreparedRay& r) { return Packet(r); }

  /// Moves each lane away from the interval's inside by 2*gamma(3): by `non_negative_factor` where t >= 0, by
  /// `negative_factor` elsewhere. Monotone, so it may follow the max/min reductions instead of each slab distance.
  /// In place: a function returning an AVX value from code built without AVX would change the ABI (-Wpsabi).
  RAYACCEL_LANE_INLINE static void widen(F& t, float non_negative_factor, float negative_factor) {
    const F non_negative = S::ge(t, S::zero());
    t = S::mul(t, S::bit_or(S::bit_and(non_negative, S::set1(non_negative_factor)),
                            S::and_not(non_negative, S::set1(negative_factor))));
  }

  /// `node` is any node type with SoA child boxes `float bounds[3][2][kWidth]` (wide/wide_node.h).
  template <class Node>
  RAYACCEL_LANE_INLINE static int intersect(const Packet& ray, const Node& node, float t_far_scalar, float* t_entry) {
    F t_near;
    const unsigned mask = intersect_lanes(ray, node, t_far_scalar, t_near);
    S::store(t_entry, t_near);
    return static_cast<int>(mask);
  }

  /// intersect() with the entry distances left in lanes (the AVX-512 traversal sorts them there); the mask comes from
  /// a mask-register compare where the lane set has one.
  template <class Node>
  RAYACCEL_LANE_INLINE static unsigned intersect_lanes(const Packet& ray, const Node& node, float t_far_scalar,
                                                       F& t_entry) {
    static_assert(sizeof(node.bounds[0][0]) == kWidth * sizeof(float), "one child box a lane");
    F t_near = ray.t_min;
    F t_far = S::set1(t_far_scalar);
    const char* planes = reinterpret_cast<const char*>(node.bounds);
    for (int a = 0; a < 3; ++a) {
      const F near_plane = S::load(reinterpret_cast<const float*>(planes + ray.near_bytes[a]));
      const F far_plane = S::load(reinterpret_cast<const float*>(planes + ray.far_bytes[a]));
      const F t0 = S::mul(S::sub(near_plane, ray.origin[a]), ray.inv_direction[a]);
      const F t1 = S::mul(S::sub(far_plane, ray.origin[a]), ray.inv_direction[a]);
      t_near = S::max(t0, t_near);  // NaN in t0 keeps the running bound (second operand)
      t_far = S::min(t1, t_far);
    }
    if (ray.t_min_non_negative) {
      // t_near >= t_min >= 0 in every lane, so it widens by the non-negative factor; t_far widens by its own
      // non-negative factor too: where t_far < 0 either factor leaves it negative, below t_near, and the lane misses
      // as it would have (the same masks and entry distances as the general case, two dependent steps shorter).
      t_near = S::mul(t_near, ray.widen_down);
      t_far = S::mul(t_far, ray.widen_up);
      if (ray.shifted) {
        // The box origin is the ray's with subnormal coordinates set to 0 (BoxTestOrigin): the exact slab distances
        // of the ray are those computed, moved by at most |s| <= slab_shift / 4. Why the result still encloses them,
        // with c >= 0 the computed near distance, tau its exact value for the moved origin (c (1 - gamma3) <= tau,
        // Ize's bound) and u = 2^-24: c * widen_down rounds to w <= tau - 8uc, so w - slab_shift rounds to at most
        // tau - slab_shift (1 - u) <= tau - |s|. The far end is the mirror image; a far distance computed below 0
        // that is exactly >= 0 is at most |s| (1 + 2 gamma3) below 0, and slab_shift >= 4|s| lifts it past.
        t_near = S::sub(t_near, ray.slab_shift);
        t_far = S::add(t_far, ray.slab_shift);
      }
    } else {
      widen(t_near, kSlabWidenDown, kSlabWidenUp);
      widen(t_far, kSlabWidenUp, kSlabWidenDown);
    }
    t_entry = t_near;
    if constexpr (requires { requires S::kMaskRegisters; }) {
      return S::le_mask(t_near, t_far);
    } else {
      return static_cast<unsigned>(S::movemask(S::le(t_near, t_far)));
    }
  }
};
RAYACCEL_LANE_CODE_END

}  // namespace rayaccel::simd
