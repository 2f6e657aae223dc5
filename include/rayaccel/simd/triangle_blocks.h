// Runs of Triangle4 blocks as leaves and cells hold them: triangle ids packed into SoA blocks of four, and a run
// tested with the watertight SIMD kernel (Woop, Benthin, Wald 2013), optionally through a block mailbox.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/scene/scene.h"
#include "rayaccel/simd/block_mailbox.h"
#include "rayaccel/simd/lane_set.h"
#include "rayaccel/simd/watertight_lanes.h"

namespace rayaccel::simd {

/// Writes primitive `id` into lane `lane` of `block`: its id, and for a triangle mesh its vertices.
inline void set_block_lane(Triangle4& block, int lane, const Scene& scene, std::uint32_t id) {
  block.prim_id[lane] = id;
  if (scene.kind() != PrimitiveKind::triangles) return;
  const auto& tri = scene.triangle(id);
  for (int v = 0; v < 3; ++v) {
    for (int a = 0; a < 3; ++a) block.vertex[v][a][lane] = tri[v][a];
  }
}

/// Validation of a triangle mesh's Triangle4 copies, the check every structure with blocks makes: the id of the first
/// lane of blocks (in order) whose vertices are not an exact copy of its triangle in `scene`; nullopt when all are.
/// Unused lanes (kInvalidPrimId) and ids outside the scene are passed over (each structure reports those itself);
/// nullopt for scenes that are not triangle meshes (their blocks hold only ids).
std::optional<std::uint32_t> first_stale_lane(std::span<const Triangle4> blocks, const Scene& scene);

/// Appends ceil(k / 4) blocks holding the k primitives of `ids`, in order; the last block's unused lanes hold
/// kInvalidPrimId and a zero triangle. For a scene that is not a triangle mesh the blocks hold only the ids (zero
/// vertices). The ids must be valid primitives (what Scene::build_references() gives the builders): a triangle with
/// coincident vertices has zero area, so Scene already keeps it out, and every copied triangle can be hit.
void pack_triangle_blocks(const Scene& scene, std::span<const std::uint32_t> ids, std::vector<Triangle4>& out);

/// The ids a run of blocks holds, padding lanes skipped (for validation and statistics).
template <class F>
void for_each_block_id(const Triangle4* blocks, std::uint32_t count, F&& f) {
  for (std::uint32_t b = 0; b < count; ++b) {
    for (int lane = 0; lane < 4; ++lane) {
      if (blocks[b].prim_id[lane] != kInvalidPrimId) f(blocks[b], lane);
    }
  }
}

/// Tests blocks[0 .. count) with the ray (`packet` over Lanes), closest hit into `hit`: pairs of blocks with eight
/// lanes when Lanes is Avx8 (only inside simd/dispatch.h's AVX entry points; an odd last block is paired with
/// itself), one block at a time when Lanes is Sse4. With Mailbox, blocks whose triangles were all tested before are
/// skipped. Returns true on any update of `hit`; any-hit queries return at the first one.
RAYACCEL_LANE_CODE_BEGIN
template <class Lanes, bool AnyHit, bool Mailbox, class Stats>
RAYACCEL_LANE_INLINE bool intersect_block_run(const TrianglePacket<Lanes>& packet, const PreparedRay& ray,
                                              const Triangle4* blocks, std::uint32_t count, BlockMailbox& mailbox,
                                              Hit& hit, Stats& stats) {
  bool found = false;
  if constexpr (Lanes::kWidth == 8 && !Mailbox) {
    // Consecutive blocks in pairs; an odd last block is paired with itself (see below), chosen without a branch.
    for (std::uint32_t b = 0; b < count; b += 2) {
      const bool both = b + 1 < count;
      const Triangle4* pair[2] = {&blocks[b], &blocks[both ? b + 1 : b]};
      stats.test_primitive(both ? 8 : 4);
      found |= intersect_triangle_lanes<Lanes>(packet, ray, pair, hit, stats);
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
        found |= intersect_triangle_lanes<Lanes>(packet, ray, pair, hit, stats);
        if (AnyHit && found) return true;
      }
    }
    if (pending) {
      // The odd block goes through the eight-lane test too, paired with itself: its triangles are tested twice
      // in one instruction stream, and a repeated test cannot change the closest hit (t < hit.t is strict).
      stats.test_primitive(4);
      pair[1] = pair[0];
      found |= intersect_triangle_lanes<Lanes>(packet, ray, pair, hit, stats);
    }
  } else {
    for (std::uint32_t b = 0; b < count; ++b) {
      if (Mailbox && mailbox.all_seen(blocks[b])) continue;
      stats.test_primitive(4);
      found |= intersect_triangles4(packet, ray, blocks[b], hit, stats);
      if (AnyHit && found) return true;
    }
  }
  return found;
}
RAYACCEL_LANE_CODE_END

}  // namespace rayaccel::simd
