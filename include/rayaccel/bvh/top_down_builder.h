// The top-down recursion shared by the binned SAH, sweep SAH and Morton builders: node allocation, leaf-size and
// depth limits (median fallback), hints passed from a split to its children, and parallel construction of large
// subtrees with tbb::parallel_invoke.
#pragma once

#include <tbb/parallel_invoke.h>

#include <atomic>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "rayaccel/bvh/build_tree.h"

namespace rayaccel {

struct TopDownLimits {
  std::uint32_t max_leaf_size = 4;          ///< no leaf holds more references
  std::uint32_t parallel_threshold = 4096;  ///< nodes with at least this many references build children in parallel
};

/// Builds a tree top-down. `split(first, refs, hint, left_hint, right_hint)` sees the references of one node (refs
/// starts at index `first` of the whole array), partitions them in place and returns the size of the left part; 0 or
/// refs.size() asks for a leaf. `hint` is what the parent's split learnt about this node's references (a
/// default-constructed Hint at the root and after a median split); the split writes its children's hints, so a
/// builder can carry what one pass over the references found (such as centroid bounds) to the next node instead of
/// reading the references again. A leaf is only made when refs.size() <= max_leaf_size, otherwise the median split is
/// used instead; below depth kBvhMedianDepth only median splits are made, so the tree never exceeds kBvhMaxDepth
/// levels. `split` is called concurrently on disjoint ranges.
template <class Hint, class SplitFn>
BuildTree build_top_down_hinted(PrimRefs refs, const TopDownLimits& limits, SplitFn&& split) {
  BuildTree tree;
  tree.refs = std::move(refs);
  const auto n = static_cast<std::uint32_t>(tree.refs.size());
  if (n == 0) return tree;
  tree.nodes.resize(2 * std::size_t{n} - 1);  // a binary tree with n non-empty leaves has at most 2n - 1 nodes
  std::atomic<std::uint32_t> next{1};
  const std::uint32_t max_leaf = limits.max_leaf_size < 1 ? 1 : limits.max_leaf_size;

  auto recurse = [&](auto& self, std::uint32_t node, std::uint32_t first, std::uint32_t count, int depth,
                     const Hint& hint) -> void {
    std::span<PrimRef> span(tree.refs.data() + first, count);
    std::size_t left = 0;
    Hint left_hint{}, right_hint{};
    if (count > 1 && depth < kBvhMedianDepth) left = split(first, span, hint, left_hint, right_hint);
    if (left == 0 || left >= count) {
      if (count <= max_leaf) {
        tree.nodes[node] = {first, count};
        return;
      }
      left = split_at_median(span);
      left_hint = right_hint = Hint{};
    }
    const std::uint32_t child = next.fetch_add(2, std::memory_order_relaxed);
    tree.nodes[node] = {child, 0};
    const auto left_count = static_cast<std::uint32_t>(left);
    auto build_left = [&] { self(self, child, first, left_count, depth + 1, left_hint); };
    auto build_right = [&] { self(self, child + 1, first + left_count, count - left_count, depth + 1, right_hint); };
    if (count >= limits.parallel_threshold) {
      tbb::parallel_invoke(build_left, build_right);
    } else {
      build_left();
      build_right();
    }
  };
  recurse(recurse, 0, 0, n, 1, Hint{});
  tree.nodes.resize(next.load());
  return tree;
}

/// build_top_down_hinted without hints: `split(first, refs)` partitions one node's references and returns the size
/// of the left part, as above.
template <class SplitFn>
BuildTree build_top_down(PrimRefs refs, const TopDownLimits& limits, SplitFn&& split) {
  struct NoHint {};
  return build_top_down_hinted<NoHint>(
      std::move(refs), limits,
      [&](std::uint32_t first, std::span<PrimRef> node_refs, const NoHint&, NoHint&, NoHint&) -> std::size_t {
        return split(first, node_refs);
      });
}

}  // namespace rayaccel
