// Avx8Masked: the eight-lane set of AVX-512 CPUs (F, VL, DQ, BW on 256-bit vectors): Avx8's operations plus what only
// AVX-512 has, compares into mask registers, vpcompressd and a permute-and-min/max sorting network (Batcher 1968).
#pragma once

#include <immintrin.h>

#include <cstdint>

#include "rayaccel/simd/isa.h"
#include "rayaccel/simd/lanes_avx2.h"

namespace rayaccel::simd {

/// Runs only inside simd/dispatch.h's AVX-512 entry point (every added function carries RAYACCEL_TARGET_AVX512).
struct Avx8Masked : Avx8 {
  static constexpr bool kMaskRegisters = true;
  using I = __m256i;
#define RAYACCEL_AVX512 RAYACCEL_TARGET_AVX512
  /// One bit a lane: a <= b (ordered, as Avx8::le then movemask).
  RAYACCEL_AVX512 static unsigned le_mask(F a, F b) { return _cvtmask8_u32(_mm256_cmp_ps_mask(a, b, _CMP_LE_OS)); }
  RAYACCEL_AVX512 static I load_u32(const std::uint32_t* p) {  ///< 32-byte aligned
    return _mm256_load_si256(reinterpret_cast<const __m256i*>(p));
  }
  /// The lanes whose bit is set in `mask`, packed to the low lanes in lane order (vpcompressd), zeros above.
  RAYACCEL_AVX512 static I compress(unsigned mask, I v) { return _mm256_maskz_compress_epi32(__mmask8(mask), v); }
  /// Lane `lane` of v, by a permute (read back from a store just made, it would wait for store forwarding).
  RAYACCEL_AVX512 static std::uint32_t extract_u32(I v, int lane) {
    return static_cast<std::uint32_t>(
        _mm256_cvtsi256_si32(_mm256_permutexvar_epi32(_mm256_set1_epi32(lane), v)));
  }
  RAYACCEL_AVX512 static void store_u32(std::uint32_t* p, I v) {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), v);
  }

  /// Sort keys of the lanes in `mask`: each distance's order-preserving bits with the low three replaced by the lane
  /// index (so keys differ and carry their lane; the key's distance is at most 7 ulps below the lane's), INT32_MIN in
  /// the other lanes (sorted last). NaN distances must not be in `mask`.
  RAYACCEL_AVX512 static I lane_keys(F t, unsigned mask) {
    const I bits = _mm256_and_si256(order_preserving_bits(_mm256_castps_si256(t)), _mm256_set1_epi32(~7));
    const I keys = _mm256_or_si256(bits, _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    return _mm256_mask_mov_epi32(_mm256_set1_epi32(INT32_MIN), __mmask8(mask), keys);
  }
  /// The distance a key stands for (bit-cast to float lanes): at most the distance it was made from.
  RAYACCEL_AVX512 static I key_distance_bits(I keys) {
    return order_preserving_bits(_mm256_and_si256(keys, _mm256_set1_epi32(~7)));
  }
  /// Float bits mapped to int32 whose signed order is the floats' order (NaN aside); its own inverse.
  RAYACCEL_AVX512 static I order_preserving_bits(I bits) {
    return _mm256_xor_si256(bits, _mm256_srli_epi32(_mm256_srai_epi32(bits, 31), 1));
  }

  /// Signed int32 lanes sorted largest first: bitonic network of six compare-exchange layers, each a shuffle and a
  /// min and a max merged under a mask (the lower lane of each pair keeps the max).
  RAYACCEL_AVX512 static I sort_descending(I v) {
    v = layer(v, _mm256_shuffle_epi32(v, 0xB1), 0x55);  // pairs (0,1) (2,3) ...
    v = layer(v, _mm256_shuffle_epi32(v, 0x1B), 0x33);  // mirrors in fours: (0,3) (1,2) ...
    v = layer(v, _mm256_shuffle_epi32(v, 0xB1), 0x55);
    v = layer(v, _mm256_permutexvar_epi32(_mm256_setr_epi32(7, 6, 5, 4, 3, 2, 1, 0), v), 0x0F);  // (i, 7 - i)
    v = layer(v, _mm256_shuffle_epi32(v, 0x4E), 0x33);  // distance two: (0,2) (1,3) ...
    v = layer(v, _mm256_shuffle_epi32(v, 0xB1), 0x55);
    return v;
  }
  /// One layer of sort_descending(): lanes in keep_max take max(x, partner), the others min(x, partner).
  RAYACCEL_AVX512 static I layer(I x, I partner, __mmask8 keep_max) {
    return _mm256_mask_max_epi32(_mm256_min_epi32(x, partner), keep_max, x, partner);
  }
  /// Interleaves a and b lane by lane: low returns a0 b0 a1 b1 a2 b2 a3 b3, high the same from lane 4 on.
  RAYACCEL_AVX512 static I interleave_low(I a, I b) {
    return _mm256_permutex2var_epi32(a, _mm256_setr_epi32(0, 8, 1, 9, 2, 10, 3, 11), b);
  }
  RAYACCEL_AVX512 static I interleave_high(I a, I b) {
    return _mm256_permutex2var_epi32(a, _mm256_setr_epi32(4, 12, 5, 13, 6, 14, 7, 15), b);
  }
  /// The lane indices of a wide node's order word (wide/wide_node.h): lane p holds bits 3p..3p+2.
  RAYACCEL_AVX512 static I order_lanes(unsigned word) {
    return _mm256_and_si256(
        _mm256_srlv_epi32(_mm256_set1_epi32(static_cast<int>(word)), _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21)),
        _mm256_set1_epi32(7));
  }
  /// Bit p set where `mask` has the bit of the lane index in lane p of `lanes` (lanes 0..7).
  RAYACCEL_AVX512 static unsigned lanes_in_mask(I lanes, unsigned mask) {
    return _cvtmask8_u32(_mm256_test_epi32_mask(_mm256_sllv_epi32(_mm256_set1_epi32(1), lanes),
                                                _mm256_set1_epi32(static_cast<int>(mask))));
  }
  /// v's lanes in the order of `lanes` (lane indices in the low three bits of each lane; a key from lane_keys will do).
  RAYACCEL_AVX512 static I gather_lanes(I lanes, I v) { return _mm256_permutexvar_epi32(lanes, v); }
#undef RAYACCEL_AVX512
};

static_assert(LaneSet<Avx8Masked>);

}  // namespace rayaccel::simd
