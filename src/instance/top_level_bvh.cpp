// TopLevelBvh: the build (binned SAH over instance boxes, then boxes fitted bottom-up), the refit (the same
// bottom-up pass over the kept tree) and its validation.
#include "rayaccel/instance/top_level_bvh.h"

#include <string>

#include "rayaccel/bvh/binned_sah_builder.h"
#include "rayaccel/core/error.h"

namespace rayaccel {

namespace {

AABB fit_boxes(const BuildTree& tree, std::vector<TopLevelNode>& nodes, std::uint32_t node) {
  const BuildNode& b = tree.nodes[node];
  AABB box;
  if (b.is_leaf()) {
    for (std::uint32_t i = b.first; i < b.first + b.count; ++i) box.extend(tree.refs[i].bounds);
  } else {
    box = merge(fit_boxes(tree, nodes, b.first), fit_boxes(tree, nodes, b.first + 1));
  }
  nodes[node] = TopLevelNode{box, b.first, b.count};
  return box;
}

AABB refit_boxes(std::vector<TopLevelNode>& nodes, const std::vector<std::uint32_t>& items,
                 std::span<const AABB> boxes, std::uint32_t node) {
  TopLevelNode& n = nodes[node];
  AABB box;
  if (n.count > 0) {
    for (std::uint32_t i = n.first; i < n.first + n.count; ++i) box.extend(boxes[items[i]]);
  } else {
    box = merge(refit_boxes(nodes, items, boxes, n.first), refit_boxes(nodes, items, boxes, n.first + 1));
  }
  nodes[node].box = box;
  return box;
}

}  // namespace

void TopLevelBvh::refit(std::span<const AABB> boxes) {
  std::size_t non_empty = 0;
  for (const AABB& box : boxes) non_empty += box.is_empty() ? 0 : 1;
  if (boxes.size() != built_count_ || non_empty != items_.size()) {
    throw Error("TopLevelBvh::refit: " + std::to_string(boxes.size()) + " boxes (" + std::to_string(non_empty) +
                " not empty), the tree was built over " + std::to_string(built_count_) + " (" +
                std::to_string(items_.size()) + " not empty)");
  }
  for (const std::uint32_t item : items_) {
    if (boxes[item].is_empty()) throw Error("TopLevelBvh::refit: box " + std::to_string(item) + " became empty");
  }
  if (!nodes_.empty()) refit_boxes(nodes_, items_, boxes, 0);
}

void TopLevelBvh::build(std::span<const AABB> boxes) {
  built_count_ = boxes.size();
  PrimRefs refs;
  refs.reserve(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    if (!boxes[i].is_empty()) refs.push_back(PrimRef{boxes[i], static_cast<std::uint32_t>(i)});
  }
  nodes_.clear();
  items_.clear();
  if (refs.empty()) return;
  BinnedSahOptions options;
  options.max_leaf_size = 1;
  const BuildTree tree = build_binned_sah(std::move(refs), options);
  nodes_.resize(tree.nodes.size());
  fit_boxes(tree, nodes_, 0);
  items_.reserve(tree.refs.size());
  for (const PrimRef& ref : tree.refs) items_.push_back(ref.prim_id);
}

std::size_t TopLevelBvh::memory_bytes() const {
  return nodes_.capacity() * sizeof(TopLevelNode) + items_.capacity() * sizeof(std::uint32_t);
}

std::vector<std::string> TopLevelBvh::validate(std::span<const AABB> boxes) const {
  std::vector<std::string> problems;
  std::vector<int> seen(boxes.size(), 0);
  struct Entry {
    std::uint32_t node;
    int depth;
  };
  std::vector<Entry> stack;
  if (!nodes_.empty()) stack.push_back({0, 1});
  while (!stack.empty()) {
    const Entry e = stack.back();
    stack.pop_back();
    const TopLevelNode& n = nodes_[e.node];
    const std::string where = "top level node " + std::to_string(e.node);
    if (e.depth > kBvhMaxDepth) problems.push_back(where + " is deeper than " + std::to_string(kBvhMaxDepth));
    if (n.count > 0) {
      for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
        if (i >= items_.size() || items_[i] >= boxes.size()) {
          problems.push_back(where + ": item " + std::to_string(i) + " out of range");
          continue;
        }
        ++seen[items_[i]];
        if (!n.box.contains(boxes[items_[i]])) {
          problems.push_back(where + ": leaf box does not contain instance " + std::to_string(items_[i]));
        }
      }
      continue;
    }
    for (std::uint32_t c = n.first; c < n.first + 2; ++c) {
      if (c >= nodes_.size() || e.depth > kBvhMaxDepth) {
        problems.push_back(where + ": child " + std::to_string(c) + " out of range");
        continue;
      }
      if (!n.box.contains(nodes_[c].box)) problems.push_back(where + ": child " + std::to_string(c) + " sticks out");
      stack.push_back({c, e.depth + 1});
    }
  }
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const int expected = boxes[i].is_empty() ? 0 : 1;
    if (seen[i] != expected) {
      problems.push_back("instance " + std::to_string(i) + " appears " + std::to_string(seen[i]) +
                         " times in the top level (expected " + std::to_string(expected) + ")");
    }
  }
  return problems;
}

}  // namespace rayaccel
