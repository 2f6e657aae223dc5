// bvh_wide's any-hit traversal: no entry distances and no sorting, the children met taken in the node's stored order
// for the ray's octant (Fuetterling et al. 2017, "Accelerated single ray tracing for wide vector units"), and the
// query ends at the first hit. Included at the end of wide_bvh.h.
#pragma once

#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel::wide {

template <class Kernel, class Stats>
RAYACCEL_LANE_INLINE void WideBvh::traverse_any_hit(const NodeArray<Kernel::kWidth>& nodes, std::uint32_t start,
                                                     const PreparedRay& ray, Hit& hit, Stats& stats) const {
  constexpr int W = Kernel::kWidth;
  if (start == kEmptyChild) return;
  // The arrays' addresses and the ray's prepared forms in locals, as traverse_closest sets them up: kept as plain
  // locals in each loop (not a shared struct) so the compiler keeps them in registers in both hot loops.
  const Node<W>* const node_at = nodes.data();
  const simd::Triangle4* const blocks = blocks_.data();
  const simd::TrianglePacket<typename Kernel::Lanes> triangle_packet(ray);
  const typename Kernel::Packet box_packet = Kernel::prepare(ray);
  // The far bound stays hit.t until the first hit ends the query, so nothing on the stack can be culled by a closer
  // hit: it holds bare references. The children met go farthest first for the ray's octant (Node::order, worked out
  // at build time from the child boxes' centres), so the subtree of the surface the ray leaves comes last.
  const float t_far = hit.t;
  const unsigned octant = ray_octant(ray.negative);
  std::uint32_t pending[kStackSize];
  int count = 0;
  std::uint32_t ref = start;
  for (;;) {
    stats.visit_node();
    if (ref & kLeafBit) {
      if (intersect_leaf<typename Kernel::Lanes, true>(ref, blocks, triangle_packet, ray, hit, stats)) return;
    } else {
      const Node<W>& node = node_at[ref];
      typename Kernel::F entry;  // entry distances, which any-hit does not use
      const unsigned mask = Kernel::intersect_lanes(box_packet, node, t_far, entry);
      if (mask) {
        for (unsigned m = mask; m; m &= m - 1) {
          prefetch_child_unbranched(node_at, blocks, node.child[__builtin_ctz(m)]);
        }
        ref = push_in_octant_order<typename Kernel::Lanes>(node, mask, node.order[octant], pending, count);
        continue;
      }
    }
    if (count == 0) return;
    ref = pending[--count];
  }
}

}  // namespace rayaccel::wide
