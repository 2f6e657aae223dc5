// How generalized rays (beams, cones) see a structure's tree, one view per family (Bvh<BV>, wide BVH, kd-tree): the
// root, the children a region may meet, a leaf's primitives, the entry-point traversal. A region is any type with
// box_outside(AABB, slack) and sphere_outside(center, radius), true only when proven.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "rayaccel/accel/kd_tree.h"
#include "rayaccel/bv/sphere_volume.h"
#include "rayaccel/bvh/bvh.h"
#include "rayaccel/core/stats.h"
#include "rayaccel/simd/isa.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel::generalized {

/// Growth of a box before a region test: covers boxes that a single ray's slab test accepts although the exact ray
/// misses them by rounding (a relative 2^-16 of the box's largest coordinate dwarfs the slab test's few ulps), so a
/// region that excludes a box also excludes every ray traversal that could enter it.
inline float region_slack(const AABB& box) {
  const float m = std::max({std::fabs(box.lo.x), std::fabs(box.lo.y), std::fabs(box.lo.z), std::fabs(box.hi.x),
                            std::fabs(box.hi.y), std::fabs(box.hi.z)});
  return m * 0x1p-16f;
}

/// Bvh<BV>: a reference is a node index. A node's own volume is tested: spheres by the ball test, every other volume
/// by its enclosing box (AABB nodes exactly so; OBB, k-DOP, hull and capsule nodes through bounds(), conservative).
template <BoundingVolume BV>
class BvhView {
 public:
  using Ref = std::uint32_t;
  explicit BvhView(const Bvh<BV>& bvh) : bvh_(bvh) {}

  bool empty() const { return bvh_.nodes().empty(); }
  Ref root() const { return 0; }
  bool is_leaf(Ref ref) const { return bvh_.nodes()[ref].is_leaf(); }

  template <class Region>
  bool outside(Ref ref, const Region& region) const {
    const BV& volume = bvh_.nodes()[ref].volume;
    if constexpr (std::is_same_v<BV, SphereVolume>) {
      return region.sphere_outside(volume.center, volume.radius);
    } else {
      const AABB box = volume.bounds();
      return region.box_outside(box, region_slack(box));
    }
  }
  /// Calls f(child) for each child of interior node `ref` whose volume the region may meet.
  template <class Region, class F>
  void for_each_child(Ref ref, const Region& region, TraversalStats& stats, F&& f) const {
    const auto& node = bvh_.nodes()[ref];
    for (const Ref child : {ref + 1, node.index}) {
      stats.visit_node();
      if (!outside(child, region)) f(child);
    }
  }
  template <class F>
  void for_each_prim(Ref leaf, F&& f) const {
    const auto& node = bvh_.nodes()[leaf];
    for (std::uint32_t slot = node.index; slot < node.index + node.count; ++slot) f(bvh_.slot_prim_id(slot));
  }
  void trace_from(Ref ref, const PreparedRay& ray, Hit& hit, TraversalStats& stats) const {
    bvh_.template trace_from<false>(ref, ray, hit, stats);
  }

 private:
  const Bvh<BV>& bvh_;
};

/// The wide BVH at its built width W: a reference is a child reference (node index, or leaf bit and blocks). Child
/// boxes live in the parent, so a reference's own box is not tested again (outside() proves nothing).
template <int W>
class WideView {
 public:
  using Ref = std::uint32_t;
  explicit WideView(const wide::WideBvh& bvh) : bvh_(bvh), isa_(W == 8 ? eight_wide_isa(bvh) : simd::Isa::sse2) {}

  /// The instruction set of the structure's own kernels: W lanes test a node's W children.
  simd::Isa isa() const { return isa_; }
  const wide::Node<W>& node(Ref ref) const { return nodes()[ref]; }

  bool empty() const { return bvh_.root() == wide::kEmptyChild; }
  Ref root() const { return bvh_.root(); }
  bool is_leaf(Ref ref) const { return (ref & wide::kLeafBit) != 0; }

  template <class Region>
  bool outside(Ref, const Region&) const { return false; }
  template <class Region, class F>
  void for_each_child(Ref ref, const Region& region, TraversalStats& stats, F&& f) const {
    const wide::Node<W>& node = nodes()[ref];
    for (int lane = 0; lane < W; ++lane) {
      if (node.child[lane] == wide::kEmptyChild) continue;
      stats.visit_node();
      const AABB box = wide::child_bounds(node, lane);
      if (!region.box_outside(box, region_slack(box))) f(node.child[lane]);
    }
  }
  template <class F>
  void for_each_prim(Ref leaf, F&& f) const {
    bvh_.for_each_leaf_prim(leaf, f);
  }
  void trace_from(Ref ref, const PreparedRay& ray, Hit& hit, TraversalStats& stats) const {
    bvh_.trace_from<false>(ref, ray, hit, stats);
  }
  /// True when trace_packet_from() runs: eight-wide nodes over triangles (WideBvh::has_packet_traversal()).
  bool has_packets() const { return W == 8 && bvh_.has_packet_traversal(); }
  /// WideBvh::intersect_packet_from(): up to eight rays from `ref`; returns the rays to trace again for a tie.
  int trace_packet_from(Ref ref, const Ray* rays, int count, Hit* hits) const {
    return bvh_.intersect_packet_from(ref, rays, count, hits);
  }
  /// WideBvh::intersect_tile_from(): up to eight packets culled together by `frustum`; returns the packets refused.
  int trace_tile_from(Ref ref, const wide::BeamFrustum& frustum, const Ray* rays, int count, Hit* hits,
                       std::uint64_t& ties, bool prove) const {
    return bvh_.intersect_tile_from(ref, frustum, rays, count, hits, ties, prove);
  }

 private:
  const wide::NodeArray<W>& nodes() const {
    if constexpr (W == 8) {
      return bvh_.nodes8();
    } else {
      return bvh_.nodes4();
    }
  }
  /// AVX-512 where the structure runs its AVX-512 kernels (its build statistic says so), else AVX2.
  static simd::Isa eight_wide_isa(const wide::WideBvh& bvh) {
    for (const BuildStatistic& s : bvh.build_statistics()) {
      if (s.name == "avx512_kernels") return s.value != 0.0 ? simd::Isa::avx512 : simd::Isa::avx2;
    }
    return simd::Isa::avx2;
  }
  const wide::WideBvh& bvh_;
  simd::Isa isa_;
};

/// The kd-tree: a reference is a node with its cell (children's cells split the parent's at the node's plane). A
/// primitive hit at a point is referenced by the cell holding the point, so cells outside a region hide nothing.
class KdView {
 public:
  struct Ref {
    std::uint32_t node;
    AABB cell;
    friend bool operator==(const Ref& a, const Ref& b) { return a.node == b.node; }
  };
  explicit KdView(const KdTree& tree) : tree_(tree) {}

  bool empty() const { return tree_.data().nodes.empty(); }
  Ref root() const { return {0, tree_.data().bounds}; }
  bool is_leaf(const Ref& ref) const { return tree_.data().nodes[ref.node].is_leaf(); }

  template <class Region>
  bool outside(const Ref& ref, const Region& region) const {
    return region.box_outside(ref.cell, region_slack(ref.cell));
  }
  template <class Region, class F>
  void for_each_child(const Ref& ref, const Region& region, TraversalStats& stats, F&& f) const {
    const KdNode& node = tree_.data().nodes[ref.node];
    const int axis = node.axis();
    Ref below{ref.node + 1, ref.cell}, above{node.above_child(), ref.cell};
    below.cell.hi[axis] = node.split;
    above.cell.lo[axis] = node.split;
    for (const Ref& child : {below, above}) {
      stats.visit_node();
      if (!outside(child, region)) f(child);
    }
  }
  template <class F>
  void for_each_prim(const Ref& leaf, F&& f) const {
    const KdNode& node = tree_.data().nodes[leaf.node];
    const std::uint32_t* ids = tree_.data().prim_indices.data() + node.prim_offset;
    for (std::uint32_t i = 0; i < node.prim_count(); ++i) f(ids[i]);
  }
  /// From the root whatever `ref` is: the kd-tree's traversal clips the ray to the root cell and walks cells in order.
  void trace_from(const Ref&, const PreparedRay& ray, Hit& hit, TraversalStats& stats) const {
    tree_.trace<false>(ray, hit, stats);
  }

 private:
  const KdTree& tree_;
};

}  // namespace rayaccel::generalized
