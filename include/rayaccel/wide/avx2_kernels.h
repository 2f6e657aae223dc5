// Eight-wide AVX2 ray/box test of the wide BVH: the robust slab test of simd_kernels.h (Ize 2013) over the eight
// children of a Node<8>. Every function carries target("avx2") so this header adds no AVX code to callers that run on
// CPUs without it; the wide BVH calls it only after checking the CPU at run time.
#pragma once

#include <immintrin.h>

#include "rayaccel/core/ray.h"
#include "rayaccel/geometry/ray_box.h"
#include "rayaccel/wide/wide_node.h"

namespace rayaccel::wide {

struct BoxKernel8 {
  static constexpr int kWidth = 8;
  struct Packet {
    __m256 origin[3];
    __m256 inv_direction[3];
    __m256 t_min;
    int near_offset[3];
  };

  __attribute__((target("avx2"))) static Packet prepare(const PreparedRay& r) {
    Packet p;
    for (int a = 0; a < 3; ++a) {
      p.origin[a] = _mm256_set1_ps(r.origin[a]);
      p.inv_direction[a] = _mm256_set1_ps(r.inv_direction[a]);
      p.near_offset[a] = r.negative[a];
    }
    p.t_min = _mm256_set1_ps(r.t_min);
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
    t_near = widen(t_near, kSlabWidenDown, kSlabWidenUp);
    t_far = widen(t_far, kSlabWidenUp, kSlabWidenDown);
    _mm256_store_ps(t_entry, t_near);
    return _mm256_movemask_ps(_mm256_cmp_ps(t_near, t_far, _CMP_LE_OQ));
  }
};

}  // namespace rayaccel::wide
