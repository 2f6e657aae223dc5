// kd-tree: 8-byte nodes, built at the median or by the O(N log N) SAH sweep with perfect splits (Wald & Havran
// 2006), traversed front to back by ray segments; triangle leaves are Triangle4 blocks for the SIMD kernel.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/option_table.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/accel/segment_traversal.h"
#include "rayaccel/geometry/ray_box.h"
#include "rayaccel/simd/dispatch.h"
#include "rayaccel/simd/triangle_blocks.h"

namespace rayaccel {

struct KdTreeOptions {
  enum class Builder { median, sah };
  Builder builder = Builder::sah;
  /// Deepest allowed leaf; 0 picks round(8 + 1.3 log2 n) (pbrt's rule). At most kKdMaxDepth.
  int max_depth = 0;
  /// Median builder: a node with at most this many references becomes a leaf.
  int leaf_size = 2;
  /// SAH cost of one traversal step and of one primitive test (Wald & Havran's K_T and K_I); with block_size 4,
  /// K_I is the cost of one Triangle4 block, which is cheap next to a step, so K_I is low: smaller values pay on
  /// small meshes but cost architectural scenes (BENCHMARKS.md, "Option choices", has the runs behind 15 and 3).
  float traversal_cost = 15.0f;
  float intersection_cost = 3.0f;
  /// SAH: fraction of the cost saved when a split cuts off an empty child (Wald & Havran use 0.2).
  float empty_bonus = 0.2f;
  /// SAH: K_I is charged per started block of this many references (triangle meshes, whose leaves are tested as
  /// Triangle4 blocks: 4); other primitive kinds are tested one by one and always use 1.
  int block_size = 4;
  /// Skip primitives this ray already tested in an earlier leaf (per-ray mailbox of 8 entries).
  bool mailbox = false;
};

/// Deepest tree the kd-tree builders produce; keeps the traversal stack bounded.
inline constexpr int kKdMaxDepth = kMaxSplitTreeDepth;

/// One kd-tree node in 8 bytes. Nodes are stored depth first: an interior node's below child (p[axis] <= split)
/// is the next node, its above child sits at above_child().
struct KdNode {
  // bytes 0-3: bits 0-1 = split axis (0, 1, 2) or 3 for a leaf; bits 2-31 = interior: index of the above child,
  //            leaf: number of primitive references.
  std::uint32_t bits = 3;
  // bytes 4-7: interior: split position (float); leaf: index of the leaf's first entry in the primitive-index array.
  union {
    float split;
    std::uint32_t prim_offset = 0;
  };

  static constexpr std::uint32_t kLeafTag = 3;
  static constexpr std::uint32_t kMaxField = (1u << 30) - 1;  ///< largest child index or count bits 2-31 hold

  static KdNode interior(int axis, float split_position, std::uint32_t above) {
    KdNode n;
    n.bits = (above << 2) | static_cast<std::uint32_t>(axis);
    n.split = split_position;
    return n;
  }
  static KdNode leaf(std::uint32_t offset, std::uint32_t count) {
    KdNode n;
    n.bits = (count << 2) | kLeafTag;
    n.prim_offset = offset;
    return n;
  }
  bool is_leaf() const { return (bits & 3u) == kLeafTag; }
  int axis() const { return static_cast<int>(bits & 3u); }
  std::uint32_t above_child() const { return bits >> 2; }
  std::uint32_t prim_count() const { return bits >> 2; }
};
static_assert(sizeof(KdNode) == 8, "kd-tree nodes are 8 bytes");

/// Bounds of the part of primitive `prim_id` inside `cell` (empty when it does not reach the cell); for triangles
/// the triangle clipped to the cell ("perfect splits"), otherwise its box intersected with the cell.
using ClipToCell = std::function<AABB(std::uint32_t prim_id, const AABB& cell)>;

/// A built kd-tree in its traversal layout.
struct KdTreeData {
  std::vector<KdNode> nodes;                ///< depth first; empty for an empty scene
  std::vector<std::uint32_t> prim_indices;  ///< leaf references, leaf by leaf
  AABB bounds;                              ///< the root cell
};

/// Median build: split at the median centroid of the (clipped) references, axes cycling x, y, z by depth, until
/// options.leaf_size or the depth limit; a reference goes to each side its clipped bounds touch.
KdTreeData build_kd_tree_median(std::span<const PrimRef> refs, const KdTreeOptions& options, const ClipToCell& clip);
/// SAH build in O(N log N) with sorted event lists and perfect splits (Wald & Havran 2006): split candidates are the
/// clipped bounds of each reference, the cost has the empty-space bonus, and a node becomes a leaf when no split
/// is cheaper than testing its primitives or at the depth limit.
KdTreeData build_kd_tree_sah(std::span<const PrimRef> refs, const KdTreeOptions& options, const ClipToCell& clip);
struct ProblemList;

/// The depth limit for n references under `options` (resolves max_depth = 0).
int kd_tree_max_depth(const KdTreeOptions& options, std::size_t n);
/// SAH cost of testing a leaf of n references: K_I per started block of options.block_size.
inline double kd_leaf_cost(const KdTreeOptions& options, std::size_t n) {
  const std::size_t b = options.block_size > 1 ? std::size_t(options.block_size) : 1;
  return double(options.intersection_cost) * double((n + b - 1) / b);
}

/// The KdTree's options: key, member, range and doc of each (the registry's options, their parsing and checks).
const OptionTable<KdTreeOptions>& kd_tree_option_table();

class KdTree final : public AcceleratorImpl<KdTree> {
 public:
  /// Throws Error naming the first option outside its range (kd_tree_option_table()).
  explicit KdTree(KdTreeOptions options = {});

  void build(const Scene& scene) override;
  std::size_t memory_bytes() const override {
    return data_.nodes.size() * sizeof(KdNode) + data_.prim_indices.size() * sizeof(std::uint32_t) +
           block_first_.size() * sizeof(std::uint32_t) + blocks_.size() * sizeof(simd::Triangle4);
  }
  std::vector<BuildStatistic> build_statistics() const override;
  std::vector<std::string> validate() const override;
  const KdTreeData& data() const { return data_; }

  /// Clips the ray to the root cell, then walks the cells it crosses front to back (segment_traversal.h).
  template <bool AnyHit, class Stats>
  void trace(const PreparedRay& ray, Hit& hit, Stats& stats) const {
    simd::run_with_lanes<kMaxIsa>(isa_, [&]<class Lanes>() RAYACCEL_LANE_LAMBDA {
      if (options_.mailbox) {
        trace_cells<Lanes, AnyHit, true>(ray, hit, stats);
      } else {
        trace_cells<Lanes, AnyHit, false>(ray, hit, stats);
      }
    });
  }

 private:
  template <class Lanes, bool AnyHit, bool Mailbox, class Stats>
  RAYACCEL_LANE_INLINE void trace_cells(const PreparedRay& ray, Hit& hit, Stats& stats) const;
  /// Copies each leaf's triangles into Triangle4 blocks (triangle meshes only).
  void build_blocks(const Scene& scene);
  void validate_blocks(ProblemList& report) const;

  KdTreeOptions options_;
  const Scene* scene_ = nullptr;
  KdTreeData data_;
  /// Triangle meshes: node i's leaf blocks are blocks_[block_first_[i] .. block_first_[i + 1]) (empty for interior
  /// nodes); the copy of data_.prim_indices that traversal reads. Empty for other primitive kinds.
  std::vector<std::uint32_t> block_first_;
  std::vector<simd::Triangle4> blocks_;
  /// Instruction set of the block tests (AVX2 at most: two blocks at a time; sse2: one, or no blocks at all).
  /// The widest kernels this structure runs: AVX2 (only bvh_wide has an AVX-512 build; the dispatch compiles no
  /// AVX-512 copy of this traversal).
  static constexpr simd::Isa kMaxIsa = simd::Isa::avx2;
  simd::Isa isa_ = simd::Isa::sse2;
  double build_ms_ = 0.0;
};

template <class Lanes, bool AnyHit, bool Mailbox, class Stats>
RAYACCEL_LANE_INLINE void KdTree::trace_cells(const PreparedRay& ray, Hit& hit, Stats& stats) const {
  float t0 = ray.t_min, t1 = ray.t_max;
  if (data_.nodes.empty() || !clip_ray_to_box(ray, data_.bounds, t0, t1)) return;
  // clip_ray_to_box widens only the far end; widen the near end too so no cell near the entry face is skipped.
  t0 = fmax_inline(ray.t_min, t0 * (t0 >= 0.0f ? kSlabWidenDown : kSlabWidenUp));
  RayMailbox<Mailbox> mailbox;
  simd::BlockMailbox block_mailbox;
  const simd::TrianglePacket<Lanes> packet(ray);
  const bool blocked = !block_first_.empty();
  const KdNode* nodes = data_.nodes.data();
  traverse_segments(0, t0, t1, hit, [&](const SegmentEntry& entry, ChildSegments& children) RAYACCEL_LANE_LAMBDA {
    const KdNode& node = nodes[entry.node];
    stats.visit_node();
    if (!node.is_leaf()) {
      const int axis = node.axis();
      const float o = ray.origin[axis], d = ray.direction[axis];
      const int side = o < node.split ? -1 : (o > node.split ? 1 : 0);
      // Rounding: 3 operations, so the exact crossing lies within gamma(3) of t_split; widen by twice that.
      float t_split = (node.split - o) * ray.inv_direction[axis];
      if (std::isinf(ray.inv_direction[axis])) t_split = (node.split - o) / d;  // 1/d overflowed (denormal d)
      const float lo = t_split * (t_split >= 0.0f ? kSlabWidenDown : kSlabWidenUp);
      const float hi = t_split * (t_split >= 0.0f ? kSlabWidenUp : kSlabWidenDown);
      children = split_segment(entry.node + 1, node.above_child(), side, d, lo, hi, entry.t0, entry.t1);
      return SegmentVisit::descend;
    }
    if (blocked) {
      const std::uint32_t first = block_first_[entry.node];
      const std::uint32_t count = block_first_[entry.node + 1] - first;
      if (simd::intersect_block_run<Lanes, AnyHit, Mailbox>(packet, ray, blocks_.data() + first, count,
                                                            block_mailbox, hit, stats) &&
          AnyHit) {
        return SegmentVisit::stop;
      }
      return SegmentVisit::leaf_done;
    }
    const std::uint32_t* ids = data_.prim_indices.data() + node.prim_offset;
    for (std::uint32_t i = 0, n = node.prim_count(); i < n; ++i) {
      if (mailbox.seen_before(ids[i])) continue;
      if (test_scene_primitive(*scene_, ids[i], ray, hit, stats) && AnyHit) return SegmentVisit::stop;
    }
    return SegmentVisit::leaf_done;
  });
}

void register_kd_tree(std::vector<AcceleratorInfo>& registry);

}  // namespace rayaccel
