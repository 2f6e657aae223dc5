// Sse4: four SSE2 lanes (every x86-64 CPU has them), the narrow lane set of the box and triangle kernels; the
// eight-lane AVX2 set is in lanes_avx2.h. A test over W lanes reads W / 4 Triangle4 blocks.
#pragma once

#include <emmintrin.h>

#include "rayaccel/simd/lane_set.h"
#include "rayaccel/simd/triangle4.h"

namespace rayaccel::simd {

/// The SIMD operations the kernels are written over, four lanes of SSE2: one wrapper per intrinsic, alike line by
/// line as in lanes_avx2.h and lanes_avx512.h.
struct Sse4 {
  static constexpr int kWidth = 4;
  using F = __m128;
  static F set1(float x) { return _mm_set1_ps(x); }
  static F zero() { return _mm_setzero_ps(); }
  static F all_ones() { return _mm_castsi128_ps(_mm_set1_epi32(-1)); }
  static F add(F a, F b) { return _mm_add_ps(a, b); }
  static F sub(F a, F b) { return _mm_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm_mul_ps(a, b); }
  static F div(F a, F b) { return _mm_div_ps(a, b); }
  static F max(F a, F b) { return _mm_max_ps(a, b); }
  static F min(F a, F b) { return _mm_min_ps(a, b); }
  static F load(const float* p) { return _mm_load_ps(p); }  ///< 16-byte aligned
  static F bit_and(F a, F b) { return _mm_and_ps(a, b); }
  static F bit_or(F a, F b) { return _mm_or_ps(a, b); }
  static F and_not(F a, F b) { return _mm_andnot_ps(a, b); }  ///< ~a & b
  static F eq(F a, F b) { return _mm_cmpeq_ps(a, b); }
  static F neq(F a, F b) { return _mm_cmpneq_ps(a, b); }
  static F lt(F a, F b) { return _mm_cmplt_ps(a, b); }
  static F le(F a, F b) { return _mm_cmple_ps(a, b); }
  static F gt(F a, F b) { return _mm_cmpgt_ps(a, b); }
  static F ge(F a, F b) { return _mm_cmpge_ps(a, b); }
  static int movemask(F a) { return _mm_movemask_ps(a); }
  static void store(float* p, F a) { _mm_storeu_ps(p, a); }
  static F load_vertex(const Triangle4* const* blocks, int v, int axis) {
    return _mm_load_ps(blocks[0]->vertex[v][axis]);
  }
  /// All-ones in lanes that hold no triangle.
  static F padding(const Triangle4* const* blocks) {
    const __m128i ids = _mm_load_si128(reinterpret_cast<const __m128i*>(blocks[0]->prim_id));
    return _mm_castsi128_ps(_mm_cmpeq_epi32(ids, _mm_set1_epi32(-1)));
  }
};
static_assert(LaneSet<Sse4>);

}  // namespace rayaccel::simd
