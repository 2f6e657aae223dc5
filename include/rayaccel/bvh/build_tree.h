// BuildTree: the tree shape a BVH builder makes from PrimRefs (boxes and ids only), before any node layout or bounding
// volume exists; SahCosts, the surface area heuristic's constants (Goldsmith & Salmon 1987, MacDonald & Booth 1990);
// and the depth limit every builder enforces so traversal can use a fixed-size stack.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/huge_page_allocator.h"
#include "rayaccel/core/primitives.h"

namespace rayaccel {

/// Most levels any built tree has (the root alone is 1 level). Traversal keeps at most one entry per level on its
/// stack, so a stack of this size never overflows; validate() checks the bound.
inline constexpr int kBvhMaxDepth = 64;
/// Depth at which builders stop choosing splits by cost and split at the median instead. A median split halves the
/// reference count, and counts fit in 32 bits, so 33 more levels always suffice.
inline constexpr int kBvhMedianDepth = kBvhMaxDepth - 33;

/// SAH constants: a node costs `traversal` per visit, a leaf `intersection` per primitive test; a ray reaches a node
/// with probability area(node) / area(root).
struct SahCosts {
  float traversal = 1.0f;     ///< cost of visiting one interior node
  float intersection = 1.0f;  ///< cost of one ray/primitive test
};

/// One node of the build tree. Leaves hold a contiguous range of BuildTree::refs.
struct BuildNode {
  std::uint32_t first = 0;  ///< leaf: first reference; interior: index of the left child (the right one is first + 1)
  std::uint32_t count = 0;  ///< leaf: number of references (>= 1); interior: 0
  bool is_leaf() const { return count > 0; }
};

/// A builder's output. Every builder keeps the references of any subtree contiguous in `refs`.
struct BuildTree {
  HugePageVector<BuildNode> nodes;  ///< nodes[0] is the root; empty when there are no references
  PrimRefs refs;                    ///< references in leaf order
  /// True when `refs` may hold one primitive several times, each with the clipped bounds of its part (SBVH).
  bool spatial_splits = false;
};

/// Box of all references' bounds.
AABB bounds_of(std::span<const PrimRef> refs);
/// Box of all references' centroids.
AABB centroid_bounds_of(std::span<const PrimRef> refs);

/// Partitions refs around their median centroid on the axis of largest centroid spread and returns the left size
/// (refs.size() / 2). Works for any input, identical centroids included: the fallback that bounds depth and leaf size.
std::size_t split_at_median(std::span<PrimRef> refs);

/// Adds to tree.nodes[node] a subtree over refs [first, first + count) made by median splits only, with leaves of at
/// most max_leaf_size references. Adds at most ceil(log2(count)) levels.
void build_median_subtree(BuildTree& tree, std::uint32_t node, std::uint32_t first, std::uint32_t count,
                          std::uint32_t max_leaf_size);

}  // namespace rayaccel

namespace rayaccel {

/// True when a node of `count` references and surface area `area` is cheaper as a leaf than split with the best
/// split found, whose unnormalized cost is sum(area(child) * blocks(child)). Compared without dividing by `area`, so
/// nodes of zero area (points) are handled: they become leaves when small enough. A leaf tests its references in
/// blocks of 2^block_shift at the price of one (0: one at a time).
inline bool sah_prefers_leaf(std::size_t count, float area, float best_split_cost, std::uint32_t max_leaf_size,
                             const SahCosts& costs, int block_shift = 0) {
  if (count > max_leaf_size) return false;
  const std::size_t blocks = (count + (std::size_t{1} << block_shift) - 1) >> block_shift;
  const float leaf = costs.intersection * static_cast<float>(blocks) * area;
  const float split = costs.traversal * area + costs.intersection * best_split_cost;
  return leaf <= split;
}

}  // namespace rayaccel
