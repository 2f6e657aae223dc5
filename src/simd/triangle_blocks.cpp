// Packing triangle ids into runs of Triangle4 blocks (see simd/triangle_blocks.h).
#include "rayaccel/simd/triangle_blocks.h"

#include <cassert>

namespace rayaccel::simd {

void pack_triangle_blocks(const Scene& scene, std::span<const std::uint32_t> ids, std::vector<Triangle4>& out) {
  int lane = 4;  // lanes used in out.back(); 4 = start a new block
  for (const std::uint32_t id : ids) {
    assert(scene.is_valid(id));  // valid triangles have nonzero area: no coincident vertices, nothing to leave out
    if (lane == 4) {
      Triangle4 block{};
      for (std::uint32_t& p : block.prim_id) p = kInvalidPrimId;
      out.push_back(block);
      lane = 0;
    }
    set_block_lane(out.back(), lane, scene, id);
    ++lane;
  }
}

std::optional<std::uint32_t> first_stale_lane(std::span<const Triangle4> blocks, const Scene& scene) {
  if (scene.kind() != PrimitiveKind::triangles) return std::nullopt;  // blocks of other kinds hold only ids
  for (const Triangle4& block : blocks) {
    for (int lane = 0; lane < 4; ++lane) {
      const std::uint32_t id = block.prim_id[lane];
      if (id == kInvalidPrimId || id >= scene.primitive_count()) continue;
      const auto& tri = scene.triangle(id);
      for (int v = 0; v < 3; ++v) {
        for (int a = 0; a < 3; ++a) {
          if (block.vertex[v][a][lane] != tri[v][a]) return id;
        }
      }
    }
  }
  return std::nullopt;
}

}  // namespace rayaccel::simd
