// The wide BVH's queries beyond the first hit: all hits (every leaf the ray's interval enters) and a branch-and-bound
// closest-point search, nearer children first; pre-split triangles in several leaves are reported once.
#include "rayaccel/bvh/bvh.h"
#include "rayaccel/geometry/ray_box.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel::wide {

namespace {
/// Calls query.test() for the triangle in lane `lane` of `block`.
template <class Query>
void test_lane(const simd::Triangle4& block, int lane, Query& query) {
  Vec3 v[3];
  for (int k = 0; k < 3; ++k) v[k] = Vec3{block.vertex[k][0][lane], block.vertex[k][1][lane], block.vertex[k][2][lane]};
  query.test(block.prim_id[lane], v[0], v[1], v[2]);
}
}  // namespace

template <class Query>
void WideBvh::test_leaf(std::uint32_t ref, Query& query) const {
  const std::uint32_t first = leaf_first_block(ref), end = first + leaf_block_count(ref);
  for (std::uint32_t b = first; b < end; ++b) {
    for (int lane = 0; lane < 4; ++lane) {
      if (blocks_[b].prim_id[lane] != kInvalidPrimId) test_lane(blocks_[b], lane, query);
    }
  }
}

template <class Kernel>
RAYACCEL_LANE_INLINE void WideBvh::find_crossings_in(const NodeArray<Kernel::kWidth>& nodes, HitList& list) const {
  constexpr int W = Kernel::kWidth;
  const PreparedRay& ray = list.ray();
  const typename Kernel::Packet box_packet = Kernel::prepare(ray);
  // Widened as the BVH's culling (bvh_cull_bound): every triangle whose computed t is within t_max is reached.
  const float t_far = bvh_cull_bound(Hit::begin(ray).t);
  // Leaves: the SIMD float path of the watertight test picks the lanes the scalar kernel may hit (bit-identical
  // decisions, see simd/watertight_lanes.h); only those go to HitList, which tests them with the scalar kernel.
  using Lanes = typename Kernel::Lanes;
  constexpr std::uint32_t kBlocksPerTest = Lanes::kWidth / 4;
  const simd::TrianglePacket<Lanes> triangle_packet(ray);
  const float t_far_hit = Hit::begin(ray).t;
  std::uint32_t stack[kStackSize];
  int top = 0;
  stack[top++] = root_;
  while (top > 0) {
    const std::uint32_t ref = stack[--top];
    if (ref & kLeafBit) {
      const std::uint32_t first = leaf_first_block(ref), end = first + leaf_block_count(ref);
      for (std::uint32_t b = first; b < end; b += kBlocksPerTest) {
        const bool odd = b + kBlocksPerTest > end;  // eight lanes over one last block: paired with itself
        const simd::Triangle4* group[2] = {&blocks_[b], &blocks_[odd ? b : b + kBlocksPerTest - 1]};
        int mask = simd::candidate_triangle_lanes<Lanes>(triangle_packet, ray, group, t_far_hit);
        if (odd) mask &= 0xF;
        for (; mask; mask &= mask - 1) {
          const int lane = __builtin_ctz(static_cast<unsigned>(mask));
          test_lane(*group[lane / 4], lane % 4, list);
        }
      }
      continue;
    }
    alignas(32) float entry[W];  // entry distances, which the box test writes and all hits do not use
    for (int mask = Kernel::intersect(box_packet, nodes[ref], t_far, entry); mask; mask &= mask - 1) {
      stack[top++] = nodes[ref].child[__builtin_ctz(static_cast<unsigned>(mask))];
    }
  }
}

template <int W>
void WideBvh::find_closest_point_in(const NodeArray<W>& nodes, ClosestPointSearch& search) const {
  struct Entry {
    std::uint32_t ref;
    double bound;  ///< lower bound on the squared distance to anything below
  };
  Entry stack[kStackSize];
  int top = 0;
  stack[top++] = {root_, 0.0};
  while (top > 0) {
    const Entry e = stack[--top];
    if (!search.may_improve(e.bound)) continue;
    if (e.ref & kLeafBit) {
      test_leaf(e.ref, search);
      continue;
    }
    const Node<W>& node = nodes[e.ref];
    // The children near enough, pushed in place and sorted there farthest first (insertion sort: at most W), so the
    // nearest is searched next and tightens the bound soonest.
    Entry* met = stack + top;
    int count = 0;
    for (int lane = 0; lane < W; ++lane) {
      if (node.child[lane] == kEmptyChild) continue;
      const Entry child{node.child[lane], search.box_lower_bound(child_bounds(node, lane))};
      if (!search.may_improve(child.bound)) continue;
      int i = count++;
      for (; i > 0 && met[i - 1].bound < child.bound; --i) met[i] = met[i - 1];
      met[i] = child;
    }
    top += count;
  }
}

void WideBvh::find_crossings(HitList& list) const {
  if (root_ == kEmptyChild) return;
  detail::require_triangle_scene(*scene_, "all-hits");
  // The children's boxes tested at once with the SIMD box kernel of the tree's width, as in trace().
  simd::run_with_lanes(isa_, [&]<class Lanes>() RAYACCEL_LANE_LAMBDA {
    if constexpr (Lanes::kWidth == 8) {
      find_crossings_in<simd::BoxKernel<Lanes>>(nodes8_, list);
    } else {
      find_crossings_in<simd::BoxKernel<Lanes>>(nodes4_, list);
    }
  });
}

void WideBvh::find_closest_point(ClosestPointSearch& search) const {
  if (root_ == kEmptyChild) return;
  detail::require_triangle_scene(*scene_, "closest-point");
  if (width_ == 8) {
    find_closest_point_in(nodes8_, search);
  } else {
    find_closest_point_in(nodes4_, search);
  }
}

}  // namespace rayaccel::wide
