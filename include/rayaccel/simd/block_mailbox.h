// A per-ray mailbox over Triangle4 blocks (Amanatides & Woo 1987; Kirk & Arvo): the spatial subdivisions meet a
// triangle in several cells, and this skips a block only when every triangle in it was already tested by the ray.
#pragma once

#include <emmintrin.h>

#include <cstdint>

#include "rayaccel/core/hit.h"
#include "rayaccel/simd/triangle4.h"

namespace rayaccel::simd {

/// Per-ray mailbox of the last eight triangle ids tested, checked a block at a time with SSE2: a block is skipped
/// only when each of its triangles is in the mailbox (skipping is safe then: a repeated test can only fail, since
/// hit.t never grows); otherwise its new ids are recorded and the whole block is tested.
struct BlockMailbox {
  alignas(16) std::uint32_t ids[8] = {kInvalidPrimId, kInvalidPrimId, kInvalidPrimId, kInvalidPrimId,
                                      kInvalidPrimId, kInvalidPrimId, kInvalidPrimId, kInvalidPrimId};
  int next = 0;
  bool all_seen(const Triangle4& block) {
    const __m128i q = _mm_load_si128(reinterpret_cast<const __m128i*>(block.prim_id));
    const __m128i lo = _mm_load_si128(reinterpret_cast<const __m128i*>(ids));
    const __m128i hi = _mm_load_si128(reinterpret_cast<const __m128i*>(ids + 4));
    __m128i seen = _mm_cmpeq_epi32(q, _mm_set1_epi32(-1));  // padding lanes count as seen
    seen = _mm_or_si128(seen, _mm_cmpeq_epi32(q, _mm_shuffle_epi32(lo, 0x00)));
    seen = _mm_or_si128(seen, _mm_cmpeq_epi32(q, _mm_shuffle_epi32(lo, 0x55)));
    seen = _mm_or_si128(seen, _mm_cmpeq_epi32(q, _mm_shuffle_epi32(lo, 0xAA)));
    seen = _mm_or_si128(seen, _mm_cmpeq_epi32(q, _mm_shuffle_epi32(lo, 0xFF)));
    seen = _mm_or_si128(seen, _mm_cmpeq_epi32(q, _mm_shuffle_epi32(hi, 0x00)));
    seen = _mm_or_si128(seen, _mm_cmpeq_epi32(q, _mm_shuffle_epi32(hi, 0x55)));
    seen = _mm_or_si128(seen, _mm_cmpeq_epi32(q, _mm_shuffle_epi32(hi, 0xAA)));
    seen = _mm_or_si128(seen, _mm_cmpeq_epi32(q, _mm_shuffle_epi32(hi, 0xFF)));
    const int mask = _mm_movemask_ps(_mm_castsi128_ps(seen));
    if (mask == 0xF) return true;
    for (int rest = ~mask & 0xF; rest; rest &= rest - 1) {
      ids[next] = block.prim_id[__builtin_ctz(static_cast<unsigned>(rest))];
      next = (next + 1) & 7;
    }
    return false;
  }
};

}  // namespace rayaccel::simd
