// Triangle4 blocks for the spatial structures: packing triangle ids into SoA blocks (see triangle_blocks.h).
#include "rayaccel/wide/triangle_blocks.h"

namespace rayaccel::wide {

std::uint32_t pack_triangle_blocks(const Scene& scene, std::span<const std::uint32_t> ids,
                                   std::vector<Triangle4>& out) {
  const bool triangles = scene.kind() == PrimitiveKind::triangles;
  std::uint32_t skipped = 0;
  int lane = 4;  // lanes used in out.back(); 4 = start a new block
  for (const std::uint32_t id : ids) {
    if (triangles && coincident_vertices(scene.triangle(id))) {
      ++skipped;
      continue;
    }
    if (lane == 4) {
      Triangle4 block{};
      for (std::uint32_t& p : block.prim_id) p = kInvalidPrimId;
      out.push_back(block);
      lane = 0;
    }
    set_block_lane(out.back(), lane, scene, id);
    ++lane;
  }
  return skipped;
}

}  // namespace rayaccel::wide
