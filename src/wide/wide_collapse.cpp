// Wide BVH collapse: a binary tree's nodes gathered into 4- or 8-wide nodes by opening the child of largest surface
// area (Wald, Benthin, Boulos 2008; Dammertz et al. 2008) or by the least SAH cost (Ylitie, Karras, Laine 2017's
// dynamic programme), children's boxes written SoA.
#include <algorithm>
#include <array>
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel::wide {

/// Boxes of every binary node; BuildTree stores children after their parent, so one backward pass suffices.
HugePageVector<AABB> WideBvh::binary_node_bounds(const BuildTree& tree) {
  HugePageVector<AABB> boxes(tree.nodes.size());
  for (std::size_t i = tree.nodes.size(); i-- > 0;) {
    const BuildNode& n = tree.nodes[i];
    if (n.is_leaf()) {
      if (std::size_t{n.first} + n.count > tree.refs.size()) {
        throw Error("wide BVH: binary tree leaf " + std::to_string(i) + " references past the end of the tree's " +
                    std::to_string(tree.refs.size()) + " references");
      }
      for (std::uint32_t r = n.first; r < n.first + n.count; ++r) boxes[i].extend(tree.refs[r].bounds);
    } else {
      // Children after their parent (as every builder stores them): the backward pass has their boxes already.
      if (n.first <= i || std::size_t{n.first} + 1 >= tree.nodes.size()) {
        throw Error("wide BVH: binary tree node " + std::to_string(i) + " has children at " +
                    std::to_string(n.first) + ", not after it within the tree's " +
                    std::to_string(tree.nodes.size()) + " nodes");
      }
      boxes[i] = merge(boxes[n.first], boxes[n.first + 1]);
    }
  }
  return boxes;
}

namespace {

/// The slots the left child takes when `plan` (a node's collapse_plan_ entry) opens the node into j slots.
int left_slots(std::uint32_t plan, int j) { return static_cast<int>((plan >> (4 * (j - 2))) & 15u); }

}  // namespace

void WideBvh::plan_collapse(const BuildTree& tree, std::uint32_t binary_node, float* slot_cost) {
  // Costs relative to the root's area, as the binary build's SAH: a wide node costs `traversal` per visit, a leaf
  // `intersection` per block of four primitives (repeated pieces counted, an upper bound).
  const BinnedSahOptions& c = config_.binary;
  const BuildNode& n = tree.nodes[binary_node];
  const float area = binary_bounds_[binary_node].surface_area();
  if (n.is_leaf()) {
    const float leaf = area * c.costs.intersection * static_cast<float>((n.count + 3) / 4);
    for (int j = 0; j < width_; ++j) slot_cost[j] = leaf;
    return;
  }
  float left[8], right[8];
  plan_collapse(tree, n.first, left);
  plan_collapse(tree, n.first + 1, right);
  // open[j - 1]: the least cost of the two subtrees sharing j slots, and the left one's share.
  float open[8];
  std::uint32_t plan = 0;
  for (int j = 2; j <= width_; ++j) {
    int best_k = 1;
    open[j - 1] = left[0] + right[j - 2];
    for (int k = 2; k < j; ++k) {
      const float cost = left[k - 1] + right[j - k - 1];
      if (cost < open[j - 1]) {
        open[j - 1] = cost;
        best_k = k;
      }
    }
    plan |= static_cast<std::uint32_t>(best_k) << (4 * (j - 2));
  }
  // One slot: the node is a wide node of its own, whose width_ slots its subtrees share.
  slot_cost[0] = area * c.costs.traversal + open[width_ - 1];
  for (int j = 2; j <= width_; ++j) {
    // Opened unless keeping the node whole is strictly cheaper (a node of its own costs more than opening it into
    // every slot, so a wide node's own binary node is always opened).
    if (slot_cost[0] < open[j - 1]) {
      plan &= ~(15u << (4 * (j - 2)));
      slot_cost[j - 1] = slot_cost[0];
    } else {
      slot_cost[j - 1] = open[j - 1];
    }
  }
  collapse_plan_[binary_node] = plan;
}

template <int W>
std::uint32_t WideBvh::emit(const BuildTree& tree, std::uint32_t binary_node, int depth, NodeArray<W>& nodes) {
  depth_ = std::max(depth_, depth);
  if (tree.nodes[binary_node].is_leaf()) return emit_leaf(tree, binary_node);
  std::array<std::uint32_t, W> children{tree.nodes[binary_node].first, tree.nodes[binary_node].first + 1};
  int child_count = 2;
  if (!collapse_plan_.empty()) {
    // The plan's choice: the node opened into W slots, each subtree opened as far as its share of them says.
    child_count = 0;
    const auto gather = [&](auto& self, std::uint32_t node, int slots) -> void {
      const int k = slots >= 2 ? left_slots(collapse_plan_[node], slots) : 0;
      if (k == 0 || tree.nodes[node].is_leaf()) {
        children[child_count++] = node;
        return;
      }
      self(self, tree.nodes[node].first, k);
      self(self, tree.nodes[node].first + 1, slots - k);
    };
    // A wide node's own binary node is always opened (plan_collapse); 0 would only come from a damaged plan.
    const int k = std::max(1, left_slots(collapse_plan_[binary_node], W));
    gather(gather, tree.nodes[binary_node].first, k);
    gather(gather, tree.nodes[binary_node].first + 1, W - k);
  }
  // Without a plan: open the inner child of largest surface area until W children are gathered. Leaves (and with a
  // plan every child: it leaves a slot free only where opening costs more) take area -1 so that they are never
  // opened.
  std::array<float, W> areas{};
  const auto openable_area = [&](std::uint32_t c) {
    return tree.nodes[c].is_leaf() || !collapse_plan_.empty() ? -1.0f : binary_bounds_[c].surface_area();
  };
  for (int i = 0; i < child_count; ++i) areas[i] = openable_area(children[i]);
  while (child_count < W) {
    int best = -1;
    float best_area = -1.0f;
    for (int i = 0; i < child_count; ++i) {
      if (areas[i] > best_area) {
        best = i;
        best_area = areas[i];
      }
    }
    if (best < 0) break;
    const std::uint32_t opened = tree.nodes[children[best]].first;
    children[best] = opened;
    areas[best] = openable_area(opened);
    children[child_count] = opened + 1;
    areas[child_count++] = openable_area(opened + 1);
  }
  const auto index = static_cast<std::uint32_t>(nodes.size());
  nodes.emplace_back();
  Node<W> node{};
  for (int lane = 0; lane < W; ++lane) {
    node.child[lane] = kEmptyChild;
    set_child_bounds(node, lane, AABB::empty());
  }
  int lane = 0;
  for (int i = 0; i < child_count; ++i) {
    const std::uint32_t c = children[i];
    const std::uint32_t ref = emit<W>(tree, c, depth + 1, nodes);
    if (ref == kEmptyChild) continue;
    node.child[lane] = ref;
    set_child_bounds(node, lane, binary_bounds_[c]);
    ++lane;
  }
  set_child_order(node);
  nodes[index] = node;
  return lane == 0 ? kEmptyChild : index;
}

template std::uint32_t WideBvh::emit<4>(const BuildTree&, std::uint32_t, int, NodeArray<4>&);
template std::uint32_t WideBvh::emit<8>(const BuildTree&, std::uint32_t, int, NodeArray<8>&);

}  // namespace rayaccel::wide
