// Avx8: eight AVX2 lanes for the box and triangle kernels (the slab test over the eight children of a wide node, the
// watertight test of two Triangle4 blocks at once). Every function carries target("avx2") so this header adds no AVX
// code to callers that run on CPUs without it; kernels over Avx8 run only inside simd/dispatch.h's AVX entry points.
#pragma once

#include <immintrin.h>

#include "rayaccel/simd/isa.h"
#include "rayaccel/simd/lane_set.h"
#include "rayaccel/simd/triangle4.h"

namespace rayaccel::simd {

/// The kernels' operations over eight AVX2 lanes (see Sse4): one Triangle4 block per 128-bit half.
struct Avx8 {
  static constexpr int kWidth = 8;
  using F = __m256;
#define RAYACCEL_AVX2 RAYACCEL_TARGET_AVX2
  RAYACCEL_AVX2 static F set1(float x) { return _mm256_set1_ps(x); }
  RAYACCEL_AVX2 static F zero() { return _mm256_setzero_ps(); }
  RAYACCEL_AVX2 static F all_ones() { return _mm256_castsi256_ps(_mm256_set1_epi32(-1)); }
  RAYACCEL_AVX2 static F add(F a, F b) { return _mm256_add_ps(a, b); }
  RAYACCEL_AVX2 static F sub(F a, F b) { return _mm256_sub_ps(a, b); }
  RAYACCEL_AVX2 static F mul(F a, F b) { return _mm256_mul_ps(a, b); }
  RAYACCEL_AVX2 static F div(F a, F b) { return _mm256_div_ps(a, b); }
  RAYACCEL_AVX2 static F max(F a, F b) { return _mm256_max_ps(a, b); }
  RAYACCEL_AVX2 static F min(F a, F b) { return _mm256_min_ps(a, b); }
  RAYACCEL_AVX2 static F load(const float* p) { return _mm256_load_ps(p); }  ///< 32-byte aligned
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
  // For the packet traversal (one child box against eight rays, wide_bvh_packets.cpp):
  RAYACCEL_AVX2 static F broadcast(const float* p) { return _mm256_broadcast_ss(p); }
  /// b where the mask lane is set (sign bit), a elsewhere.
  RAYACCEL_AVX2 static F blend(F a, F b, F mask) { return _mm256_blendv_ps(a, b, mask); }
  /// All-ones in the lanes whose bit is set in `bits`.
  RAYACCEL_AVX2 static F lanes_from_bits(int bits) {
    const __m256i lane_bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    const __m256i set = _mm256_and_si256(_mm256_set1_epi32(bits), lane_bits);
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(set, lane_bits));
  }
  /// The smallest lane.
  RAYACCEL_AVX2 static float horizontal_min(F a) {
    __m128 m = _mm_min_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1));
    m = _mm_min_ps(m, _mm_movehl_ps(m, m));
    m = _mm_min_ss(m, _mm_shuffle_ps(m, m, 1));
    return _mm_cvtss_f32(m);
  }
#undef RAYACCEL_AVX2
};

static_assert(LaneSet<Avx8>);

}  // namespace rayaccel::simd
