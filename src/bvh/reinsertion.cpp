// Insertion-based tree optimisation (Bittner, Hapala & Havran 2013): selection by the inefficiency measures, removal,
// branch-and-bound search for the cheapest place, reinsertion; the tree rewritten in builder order at the end.
#include "rayaccel/bvh/reinsertion.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

namespace rayaccel {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

/// The tree as linked nodes, so subtrees can move: children[i] = {kNone, kNone} for a leaf.
class LinkedTree {
 public:
  LinkedTree(const BuildTree& tree, const ReinsertionOptions& options)
      : nodes_(tree.nodes.begin(), tree.nodes.end()),
        parent_(nodes_.size(), kNone),
        children_(nodes_.size(), {kNone, kNone}),
        box_(nodes_.size()),
        costs_(options.costs),
        block_shift_(__builtin_ctz(options.block_size)) {
    for (std::size_t i = nodes_.size(); i-- > 0;) {  // children follow their parent: one backward pass
      const BuildNode& n = nodes_[i];
      if (n.is_leaf()) {
        for (std::uint32_t r = n.first; r < n.first + n.count; ++r) box_[i].extend(tree.refs[r].bounds);
      } else {
        children_[i] = {n.first, n.first + 1};
        parent_[n.first] = parent_[n.first + 1] = static_cast<std::uint32_t>(i);
        box_[i] = merge(box_[n.first], box_[n.first + 1]);
      }
    }
  }

  /// Area-weighted SAH cost: traversal per interior node, intersection per started block of a leaf.
  double cost() const {
    double total = 0.0;
    for (std::size_t i = 0; i < nodes_.size(); ++i) total += double(box_[i].surface_area()) * weight(i);
    return total;
  }

  /// Interior nodes (not the root) by Bittner et al.'s combined measure, worst first: `count` of them.
  std::vector<std::uint32_t> worst_nodes(std::size_t count) const {
    std::vector<std::pair<float, std::uint32_t>> keyed;
    for (std::uint32_t i = 0; i < nodes_.size(); ++i) {
      if (i == root_ || is_leaf(i)) continue;
      const float area = box_[i].surface_area();
      const float a0 = box_[children_[i][0]].surface_area(), a1 = box_[children_[i][1]].surface_area();
      const float least = std::max(std::min(a0, a1), std::numeric_limits<float>::min());
      const float mean = std::max(0.5f * (a0 + a1), std::numeric_limits<float>::min());
      keyed.push_back({area * (area / mean) * (area / least), i});
    }
    count = std::min(count, keyed.size());
    std::partial_sort(keyed.begin(), keyed.begin() + static_cast<std::ptrdiff_t>(count), keyed.end(),
                      [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<std::uint32_t> out;
    for (std::size_t k = 0; k < count; ++k) out.push_back(keyed[k].second);
    return out;
  }

  bool is_leaf(std::uint32_t i) const { return children_[i][0] == kNone; }
  std::uint32_t child(std::uint32_t i, int k) const { return children_[i][k]; }

  /// Takes `node` (not the root) out with its parent, whose place its sibling takes, and puts it back beside the
  /// node where it adds the least cost, the parent reused as their new parent. True when the place changed.
  bool move(std::uint32_t node) {
    const std::uint32_t parent = parent_[node];
    if (parent == kNone) return false;  // the root (earlier moves can make a selected node's child the root)
    const std::uint32_t sibling = children_[parent][children_[parent][0] == node ? 1 : 0];
    replace_child(parent, sibling);  // sibling takes parent's place
    refit_from(parent_[sibling]);
    const std::uint32_t place = cheapest_place(box_[node]);
    // Put back: parent over {place, node}, in place's position.
    replace_child(place, parent);
    children_[parent] = {place, node};
    parent_[place] = parent_[node] = parent;
    refit_from(parent);
    return place != sibling;
  }

  int depth() const {
    int deepest = 0;
    std::vector<std::pair<std::uint32_t, int>> stack{{root_, 1}};
    while (!stack.empty()) {
      const auto [i, d] = stack.back();
      stack.pop_back();
      deepest = std::max(deepest, d);
      if (!is_leaf(i)) {
        stack.push_back({children_[i][0], d + 1});
        stack.push_back({children_[i][1], d + 1});
      }
    }
    return deepest;
  }

  /// Writes the tree back in builder order: depth first, each pair of children side by side after their parent.
  void write(BuildTree& tree) const {
    HugePageVector<BuildNode> out(nodes_.size());
    std::vector<std::pair<std::uint32_t, std::uint32_t>> stack{{root_, 0}};  // (linked node, slot in out)
    std::uint32_t next = 1;
    while (!stack.empty()) {
      const auto [i, slot] = stack.back();
      stack.pop_back();
      if (is_leaf(i)) {
        out[slot] = nodes_[i];
        continue;
      }
      out[slot] = {next, 0};
      stack.push_back({children_[i][1], next + 1});
      stack.push_back({children_[i][0], next});
      next += 2;
    }
    tree.nodes = std::move(out);
  }

 private:
  double weight(std::size_t i) const {
    if (!nodes_[i].is_leaf() || children_[i][0] != kNone) return costs_.traversal;
    const std::uint32_t blocks = (nodes_[i].count + (1u << block_shift_) - 1) >> block_shift_;
    return double(costs_.intersection) * blocks;
  }

  /// Puts `replacement` where `old` hangs (under old's parent, or as the root).
  void replace_child(std::uint32_t old, std::uint32_t replacement) {
    const std::uint32_t up = parent_[old];
    parent_[replacement] = up;
    if (up == kNone) {
      root_ = replacement;
    } else {
      children_[up][children_[up][0] == old ? 0 : 1] = replacement;
    }
  }

  void refit_from(std::uint32_t i) {
    for (; i != kNone; i = parent_[i]) box_[i] = merge(box_[children_[i][0]], box_[children_[i][1]]);
  }

  /// Branch and bound from the root: a place X costs area(X + box) for the new parent plus what the box adds to
  /// every ancestor of X (the induced cost); a subtree is skipped once its induced cost plus area(box), a lower bound
  /// of any place in it, is no better than the best found.
  std::uint32_t cheapest_place(const AABB& box) const {
    const double own = box.surface_area();
    using Entry = std::pair<double, std::uint32_t>;  // induced cost, node
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
    queue.push({0.0, root_});
    std::uint32_t best = root_;
    double best_cost = std::numeric_limits<double>::infinity();
    while (!queue.empty()) {
      const auto [induced, x] = queue.top();
      queue.pop();
      if (induced + own >= best_cost) break;
      const double merged = merge(box_[x], box).surface_area();
      if (induced + merged < best_cost) {
        best_cost = induced + merged;
        best = x;
      }
      if (is_leaf(x)) continue;
      const double below = induced + merged - double(box_[x].surface_area());
      if (below + own < best_cost) {
        queue.push({below, children_[x][0]});
        queue.push({below, children_[x][1]});
      }
    }
    return best;
  }

  std::vector<BuildNode> nodes_;  ///< leaves' reference ranges (interior entries unused after construction)
  std::vector<std::uint32_t> parent_;
  std::vector<std::array<std::uint32_t, 2>> children_;
  std::vector<AABB> box_;
  SahCosts costs_;
  int block_shift_ = 0;
  std::uint32_t root_ = 0;
};

}  // namespace

ReinsertionResult reinsert_nodes(BuildTree& tree, const ReinsertionOptions& options) {
  ReinsertionResult result;
  if (tree.nodes.size() < 5) return result;  // nothing can move in a root with two leaves
  LinkedTree linked(tree, options);
  result.cost_before = result.cost_after = linked.cost();
  const auto per_batch = static_cast<std::size_t>(
      std::max(1.0, std::ceil(double(options.batch_fraction) * double(tree.nodes.size() / 2))));
  for (; result.batches < options.max_batches;) {
    ++result.batches;
    for (std::uint32_t node : linked.worst_nodes(per_batch)) {
      // Its children now: earlier moves of this round may have reused it as another pair's parent.
      const std::uint32_t first = linked.child(node, 0), second = linked.child(node, 1);
      result.moves += linked.move(first) ? 1 : 0;
      result.moves += linked.move(second) ? 1 : 0;
    }
    const double cost = linked.cost();
    const bool enough = cost < result.cost_after * (1.0 - double(options.min_gain));
    result.cost_after = std::min(cost, result.cost_after);
    if (!enough) break;
  }
  if (linked.depth() > kBvhMaxDepth - 8) {  // room for what the collapse and the traversal stack assume
    result.cost_after = result.cost_before;
    result.moves = 0;
    return result;
  }
  linked.write(tree);
  return result;
}

}  // namespace rayaccel
