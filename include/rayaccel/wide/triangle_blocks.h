// Triangle4 blocks for the spatial structures (kd-tree, uniform grid): packing a list of triangle ids into SoA blocks
// of four (copies of the vertices; triangles with coincident vertices left out, they are never hit), the test of a
// run of blocks with the watertight SIMD kernel of simd_kernels.h (Woop, Benthin, Wald 2013; four lanes with SSE2 or
// two blocks at once with AVX2), and a per-ray mailbox over blocks (Amanatides & Woo 1987; Kirk & Arvo) that skips a
// block only when every triangle in it was already tested by the ray.
#pragma once

#include <emmintrin.h>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/core/scene.h"
#include "rayaccel/wide/simd_kernels.h"

namespace rayaccel::wide {

/// Exactly coincident vertex positions: such a triangle's edge functions cancel exactly (one is 0, the other two are
/// negatives of each other), so it is never hit and can be left out of the blocks without changing any answer.
inline bool coincident_vertices(const std::array<Vec3, 3>& t) { return t[0] == t[1] || t[1] == t[2] || t[2] == t[0]; }

/// Writes primitive `id` into lane `lane` of `block`: its id, and for a triangle mesh its vertices.
inline void set_block_lane(Triangle4& block, int lane, const Scene& scene, std::uint32_t id) {
  block.prim_id[lane] = id;
  if (scene.kind() != PrimitiveKind::triangles) return;
  const auto& tri = scene.triangle(id);
  for (int v = 0; v < 3; ++v) {
    for (int a = 0; a < 3; ++a) block.vertex[v][a][lane] = tri[v][a];
  }
}

/// Appends ceil(k / 4) blocks holding the k triangles of `ids` that do not have coincident vertices, in order; the
/// last block's unused lanes hold kInvalidPrimId and a zero triangle. For a scene that is not a triangle mesh the
/// blocks hold only the ids (zero vertices) and nothing is left out. Returns the number of ids left out.
std::uint32_t pack_triangle_blocks(const Scene& scene, std::span<const std::uint32_t> ids,
                                   std::vector<Triangle4>& out);

/// The ids a run of blocks holds, padding lanes skipped (for validation and statistics).
template <class F>
void for_each_block_id(const Triangle4* blocks, std::uint32_t count, F&& f) {
  for (std::uint32_t b = 0; b < count; ++b) {
    for (int lane = 0; lane < 4; ++lane) {
      if (blocks[b].prim_id[lane] != kInvalidPrimId) f(blocks[b], lane);
    }
  }
}

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

/// Tests blocks[0 .. count) with the ray (`packet` over Lanes), closest hit into `hit`: pairs of blocks with eight
/// lanes when Lanes is Avx8 (only from AVX2 functions, see WideBvh::trace_avx2; an odd last block is paired with
/// itself), one block at a time when Lanes is Sse4. With Mailbox,
/// blocks whose triangles were all tested before are skipped. Returns true on any update of `hit`; any-hit queries
/// return at the first one.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
template <class Lanes, bool AnyHit, bool Mailbox, class Stats>
inline bool intersect_block_run(const TrianglePacket<Lanes>& packet, const PreparedRay& ray, const Triangle4* blocks,
                                std::uint32_t count, BlockMailbox& mailbox, Hit& hit, Stats& stats) {
  bool found = false;
  if constexpr (Lanes::kWidth == 8 && !Mailbox) {
    // Consecutive blocks in pairs; an odd last block is paired with itself (see below), chosen without a branch.
    for (std::uint32_t b = 0; b < count; b += 2) {
      const bool both = b + 1 < count;
      const Triangle4* pair[2] = {&blocks[b], &blocks[both ? b + 1 : b]};
      stats.test_primitive(both ? 8 : 4);
      found |= intersect_triangle_lanes<Lanes>(packet, ray, pair, hit);
      if (AnyHit && found) return true;
    }
  } else if constexpr (Lanes::kWidth == 8) {
    const Triangle4* pair[2];
    int pending = 0;
    for (std::uint32_t b = 0; b < count; ++b) {
      if (Mailbox && mailbox.all_seen(blocks[b])) continue;
      pair[pending++] = &blocks[b];
      if (pending == 2) {
        pending = 0;
        stats.test_primitive(8);
        found |= intersect_triangle_lanes<Lanes>(packet, ray, pair, hit);
        if (AnyHit && found) return true;
      }
    }
    if (pending) {
      // The odd block goes through the eight-lane test too, paired with itself: its triangles are tested twice
      // in one instruction stream, and a repeated test cannot change the closest hit (t < hit.t is strict).
      stats.test_primitive(4);
      pair[1] = pair[0];
      found |= intersect_triangle_lanes<Lanes>(packet, ray, pair, hit);
    }
  } else {
    for (std::uint32_t b = 0; b < count; ++b) {
      if (Mailbox && mailbox.all_seen(blocks[b])) continue;
      stats.test_primitive(4);
      found |= intersect_triangles4(packet, ray, blocks[b], hit);
      if (AnyHit && found) return true;
    }
  }
  return found;
}
#pragma GCC diagnostic pop

}  // namespace rayaccel::wide
