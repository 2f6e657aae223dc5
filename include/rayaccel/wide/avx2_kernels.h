// Eight-wide AVX2 ray/box test of the wide BVH: the robust slab test of simd_kernels.h (Ize 2013) over the eight
// children of a Node<8>. Every function carries target("avx2") so this header adds no AVX code to callers that run on
// CPUs without it; the wide BVH calls it only after checking the CPU at run time.
#pragma once

#include <immintrin.h>

#include "rayaccel/core/ray.h"
#include "rayaccel/geometry/ray_box.h"
#include "rayaccel/wide/simd_kernels.h"
#include "rayaccel/wide/wide_node.h"

namespace rayaccel::wide {

/// The triangle test's operations over eight AVX2 lanes (see Sse4): one Triangle4 block per 128-bit half.
struct Avx8 {
  static constexpr int kWidth = 8;
  using F = __m256;
#define RAYACCEL_AVX2 __attribute__((target("avx2")))
  RAYACCEL_AVX2 static F set1(float x) { return _mm256_set1_ps(x); }
  RAYACCEL_AVX2 static F zero() { return _mm256_setzero_ps(); }
  RAYACCEL_AVX2 static F all_ones() { return _mm256_castsi256_ps(_mm256_set1_epi32(-1)); }
  RAYACCEL_AVX2 static F add(F a, F b) { return _mm256_add_ps(a, b); }
  RAYACCEL_AVX2 static F sub(F a, F b) { return _mm256_sub_ps(a, b); }
  RAYACCEL_AVX2 static F mul(F a, F b) { return _mm256_mul_ps(a, b); }
  RAYACCEL_AVX2 static F div(F a, F b) { return _mm256_div_ps(a, b); }
  RAYACCEL_AVX2 static F max(F a, F b) { return _mm256_max_ps(a, b); }
  RAYACCEL_AVX2 static F bit_and(F a, F b) { return _mm256_and_ps(a, b); }
  RAYACCEL_AVX2 static F bit_or(F a, F b) { return _mm256_or_ps(a, b); }
  RAYACCEL_AVX2 static F and_not(F a, F b) { return _mm256_andnot_ps(a, b); }
  RAYACCEL_AVX2 static F eq(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
  RAYACCEL_AVX2 static F neq(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_NEQ_UQ); }  // as _mm_cmpneq_ps
  RAYACCEL_AVX2 static F lt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LT_OS); }
  RAYACCEL_AVX2 static F le(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LE_OS); }
  RAYACCEL_AVX2 static F gt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GT_OS); }
  RAYACCEL_AVX2 static F ge(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GE_OS); }
  RAYACCEL_AVX2 static int movemask(F a) { return _mm256_movemask_ps(a); }
  RAYACCEL_AVX2 static void store(float* p, F a) { _mm256_storeu_ps(p, a); }
  RAYACCEL_AVX2 static F load_vertex(const Triangle4* const* blocks, int v, int axis) {
    return _mm256_set_m128(_mm_load_ps(blocks[1]->vertex[v][axis]), _mm_load_ps(blocks[0]->vertex[v][axis]));
  }
  RAYACCEL_AVX2 static F padding(const Triangle4* const* blocks) {
    const __m256i ids = _mm256_set_m128i(_mm_load_si128(reinterpret_cast<const __m128i*>(blocks[1]->prim_id)),
                                         _mm_load_si128(reinterpret_cast<const __m128i*>(blocks[0]->prim_id)));
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(ids, _mm256_set1_epi32(-1)));
  }
#undef RAYACCEL_AVX2
};

struct BoxKernel8 {
  static constexpr int kWidth = 8;
  using Lanes = Avx8;  ///< lanes of the leaf test used with this node width
  struct Packet {
    __m256 origin[3];
    __m256 inv_direction[3];
    __m256 t_min;
    __m256 widen_down, widen_up, slab_shift;  ///< see BoxTestOrigin
    int near_offset[3];
    bool t_min_non_negative;  ///< then every entry distance is >= 0 and the widening needs no per-lane sign test
    bool shifted;             ///< slab_shift != 0: the origin was moved off subnormal coordinates
  };

  __attribute__((target("avx2"))) static Packet prepare(const PreparedRay& r) {
    Packet p;
    const BoxTestOrigin box_origin(r);
    p.widen_down = _mm256_set1_ps(box_origin.widen_down);
    p.widen_up = _mm256_set1_ps(box_origin.widen_up);
    p.slab_shift = _mm256_set1_ps(box_origin.slab_shift);
    p.shifted = box_origin.slab_shift != 0.0f;
    for (int a = 0; a < 3; ++a) {
      p.origin[a] = _mm256_set1_ps(box_origin.origin[a]);
      p.inv_direction[a] = _mm256_set1_ps(r.inv_direction[a]);
      p.near_offset[a] = r.negative[a];
    }
    p.t_min = _mm256_set1_ps(r.t_min);
    p.t_min_non_negative = r.t_min >= 0.0f;
    return p;
  }

  __attribute__((target("avx2"))) static __m256 widen(__m256 t, float non_negative_factor, float negative_factor) {
    const __m256 non_negative = _mm256_cmp_ps(t, _mm256_setzero_ps(), _CMP_GE_OQ);
    return _mm256_mul_ps(t, _mm256_blendv_ps(_mm256_set1_ps(negative_factor), _mm256_set1_ps(non_negative_factor),
                                             non_negative));
  }

  /// Same contract as intersect_boxes4(): lane mask of children met within [t_min, t_far], entries to t_entry.
  __attribute__((target("avx2"))) static int intersect(const Packet& ray, const Node<8>& node, float t_far_scalar,
                                                       float* t_entry) {
    __m256 t_near = ray.t_min;
    __m256 t_far = _mm256_set1_ps(t_far_scalar);
    for (int a = 0; a < 3; ++a) {
      const __m256 near_plane = _mm256_load_ps(node.bounds[a][ray.near_offset[a]]);
      const __m256 far_plane = _mm256_load_ps(node.bounds[a][1 - ray.near_offset[a]]);
      const __m256 t0 = _mm256_mul_ps(_mm256_sub_ps(near_plane, ray.origin[a]), ray.inv_direction[a]);
      const __m256 t1 = _mm256_mul_ps(_mm256_sub_ps(far_plane, ray.origin[a]), ray.inv_direction[a]);
      t_near = _mm256_max_ps(t0, t_near);  // NaN in t0 keeps the running bound (second operand)
      t_far = _mm256_min_ps(t1, t_far);
    }
    if (ray.t_min_non_negative) {
      // t_near >= t_min >= 0 in every lane, so it widens by the non-negative factor; t_far widens by its own
      // non-negative factor too: where t_far < 0 either factor leaves it negative, below t_near, and the lane misses
      // as it would have (the same masks and entry distances as the general case, two dependent steps shorter).
      t_near = _mm256_mul_ps(t_near, ray.widen_down);
      t_far = _mm256_mul_ps(t_far, ray.widen_up);
      if (ray.shifted) {
        // The box origin is the ray's with subnormal coordinates set to 0 (BoxTestOrigin): the exact slab distances
        // of the ray are those computed, moved by at most |s| <= slab_shift / 4. Why the result still encloses them,
        // with c >= 0 the computed near distance, tau its exact value for the moved origin (c (1 - gamma3) <= tau,
        // Ize's bound) and u = 2^-24: c * widen_down rounds to w <= tau - 8uc, so w - slab_shift rounds to at most
        // tau - slab_shift (1 - u) <= tau - |s|. The far end is the mirror image; a far distance computed below 0
        // that is exactly >= 0 is at most |s| (1 + 2 gamma3) below 0, and slab_shift >= 4|s| lifts it past.
        t_near = _mm256_sub_ps(t_near, ray.slab_shift);
        t_far = _mm256_add_ps(t_far, ray.slab_shift);
      }
    } else {
      t_near = widen(t_near, kSlabWidenDown, kSlabWidenUp);
      t_far = widen(t_far, kSlabWidenUp, kSlabWidenDown);
    }
    _mm256_store_ps(t_entry, t_near);
    return _mm256_movemask_ps(_mm256_cmp_ps(t_near, t_far, _CMP_LE_OQ));
  }
};

}  // namespace rayaccel::wide
