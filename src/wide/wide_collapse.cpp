// Wide BVH collapse: a binary tree's nodes gathered into 4- or 8-wide nodes by opening the child of largest surface
// area (Wald, Benthin, Boulos 2008; Dammertz et al. 2008), children's boxes written SoA.
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

template <int W>
std::uint32_t WideBvh::emit(const BuildTree& tree, std::uint32_t binary_node, int depth, NodeArray<W>& nodes) {
  depth_ = std::max(depth_, depth);
  if (tree.nodes[binary_node].is_leaf()) return emit_leaf(tree, binary_node);
  // Open the inner child of largest surface area until W children are gathered.
  // Leaves take area -1 so that they are never opened.
  std::array<std::uint32_t, W> children{tree.nodes[binary_node].first, tree.nodes[binary_node].first + 1};
  std::array<float, W> areas{};
  const auto openable_area = [&](std::uint32_t c) {
    return tree.nodes[c].is_leaf() ? -1.0f : binary_bounds_[c].surface_area();
  };
  areas[0] = openable_area(children[0]);
  areas[1] = openable_area(children[1]);
  int child_count = 2;
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
  nodes[index] = node;
  return lane == 0 ? kEmptyChild : index;
}

template std::uint32_t WideBvh::emit<4>(const BuildTree&, std::uint32_t, int, NodeArray<4>&);
template std::uint32_t WideBvh::emit<8>(const BuildTree&, std::uint32_t, int, NodeArray<8>&);

}  // namespace rayaccel::wide
