// PLOC (Meister & Bittner 2018): mutual-nearest-neighbour clustering in Morton order, then SAH leaf collapsing.
#include "rayaccel/bvh/ploc_builder.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <tuple>

#include "rayaccel/bvh/morton.h"

namespace rayaccel {

namespace {

struct Cluster {
  AABB box;
  std::uint32_t left = 0, right = 0;  ///< children (interior); for a leaf cluster, left is its reference index
  std::uint32_t count = 1;            ///< references below
  bool leaf = true;                   ///< a single reference
  bool collapse = false;              ///< emitted as one leaf holding every reference below
};

/// Nodes are created children-first, so each cluster's index is above its children's.
std::vector<Cluster> cluster(const PrimRefs& refs, std::uint32_t radius) {
  std::vector<Cluster> nodes(refs.size());
  for (std::uint32_t i = 0; i < refs.size(); ++i) nodes[i] = {refs[i].bounds, i, 0, 1, true, false};
  std::vector<std::uint32_t> active(refs.size());
  for (std::uint32_t i = 0; i < refs.size(); ++i) active[i] = i;
  std::vector<std::uint32_t> nearest(refs.size());
  nodes.reserve(2 * refs.size());
  while (active.size() > 1) {
    const auto n = static_cast<std::uint32_t>(active.size());
    // Each i picks the j whose pair {i, j} is least by (distance, |i - j|, min(i, j) odd, min(i, j)): a strict
    // total order on pairs, so the least pair is mutual and every round merges at least once. On equal distances
    // (coincident primitives) each i prefers a neighbour, and of the two the one pairing (0, 1), (2, 3), ...: a
    // round then halves them instead of merging one pair (which made 50,000 copies of a triangle quadratic).
    tbb::parallel_for(std::uint32_t{0}, n, [&](std::uint32_t i) {
      const AABB& box = nodes[active[i]].box;
      const std::uint32_t lo = i > radius ? i - radius : 0, hi = std::min(n - 1, i + radius);
      float best = std::numeric_limits<float>::infinity();
      std::uint32_t best_j = i == 0 ? 1 : i - 1;
      bool first = true;
      const auto tie_key = [i](std::uint32_t j) {
        const std::uint32_t low = std::min(i, j);
        return std::tuple(i > j ? i - j : j - i, low & 1u, low);
      };
      for (std::uint32_t j = lo; j <= hi; ++j) {
        if (j == i) continue;
        const float d = merge(box, nodes[active[j]].box).surface_area();
        if (first || d < best || (d == best && tie_key(j) < tie_key(best_j))) {
          best = d;
          best_j = j;
          first = false;
        }
      }
      nearest[i] = best_j;
    });
    std::vector<std::uint32_t> next;
    next.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t j = nearest[i];
      if (nearest[j] != i) {
        next.push_back(active[i]);
      } else if (i < j) {
        const Cluster& a = nodes[active[i]];
        const Cluster& b = nodes[active[j]];
        nodes.push_back({merge(a.box, b.box), active[i], active[j], a.count + b.count, false, false});
        next.push_back(static_cast<std::uint32_t>(nodes.size() - 1));
      }
    }
    active = std::move(next);
  }
  return nodes;
}

/// Marks subtrees to emit as single leaves: at most max_leaf_size references and no costlier than split (SAH).
void mark_collapsed(std::vector<Cluster>& nodes, const PlocOptions& config) {
  std::vector<float> cost(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    Cluster& c = nodes[i];
    const float area = c.box.surface_area();
    const float as_leaf = config.costs.intersection * static_cast<float>(c.count) * area;
    if (c.leaf) {
      cost[i] = as_leaf;
      continue;
    }
    const float as_split = config.costs.traversal * area + cost[c.left] + cost[c.right];
    c.collapse = c.count <= config.max_leaf_size && as_leaf <= as_split;
    cost[i] = c.collapse ? as_leaf : as_split;
  }
}

class Emitter {
 public:
  Emitter(const std::vector<Cluster>& nodes, const PrimRefs& refs, BuildTree& tree,
          std::uint32_t max_leaf_size)
      : nodes_(nodes), refs_(refs), tree_(tree), max_leaf_size_(max_leaf_size) {}

  /// Emits cluster c as tree.nodes[node]; depth is the level of `node` (root 1).
  void emit(std::uint32_t c, std::uint32_t node, int depth) {
    const Cluster& cl = nodes_[c];
    if (cl.leaf || cl.collapse || depth >= kBvhMedianDepth) {
      const auto first = static_cast<std::uint32_t>(tree_.refs.size());
      append_refs(c);
      build_median_subtree(tree_, node, first, cl.count, max_leaf_size_);
      return;
    }
    const auto child = static_cast<std::uint32_t>(tree_.nodes.size());
    tree_.nodes.resize(tree_.nodes.size() + 2);
    tree_.nodes[node] = {child, 0};
    emit(cl.left, child, depth + 1);
    emit(cl.right, child + 1, depth + 1);
  }

 private:
  void append_refs(std::uint32_t c) {
    std::vector<std::uint32_t> pending{c};
    while (!pending.empty()) {
      const Cluster& cl = nodes_[pending.back()];
      pending.pop_back();
      if (cl.leaf) {
        tree_.refs.push_back(refs_[cl.left]);
      } else {
        pending.push_back(cl.right);
        pending.push_back(cl.left);
      }
    }
  }

  const std::vector<Cluster>& nodes_;
  const PrimRefs& refs_;
  BuildTree& tree_;
  std::uint32_t max_leaf_size_;
};

}  // namespace

BuildTree build_ploc(PrimRefs refs, const PlocOptions& config) {
  BuildTree tree;
  if (refs.empty()) return tree;
  sort_by_morton_code(refs);
  std::vector<Cluster> nodes = cluster(refs, std::max<std::uint32_t>(config.search_radius, 1));
  mark_collapsed(nodes, config);
  tree.refs.reserve(refs.size());
  tree.nodes.reserve(2 * refs.size());
  tree.nodes.resize(1);
  Emitter(nodes, refs, tree, std::max<std::uint32_t>(config.max_leaf_size, 1))
      .emit(static_cast<std::uint32_t>(nodes.size() - 1), 0, 1);
  return tree;
}

}  // namespace rayaccel
