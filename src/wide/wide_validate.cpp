// Wide BVH validation: every reference in range, child boxes inside their parents, leaf copies equal to the scene,
// every valid primitive reachable, depth within the traversal stack.
#include <string>
#include <vector>

#include "rayaccel/accel/validation_report.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel::wide {

template <int W>
void WideBvh::validate_nodes(const NodeArray<W>& nodes, std::vector<std::string>& problems) const {
  std::vector<std::uint8_t> seen(scene_->primitive_count(), 0);
  struct Item {
    std::uint32_t ref;
    AABB box;
    int depth;
  };
  std::vector<Item> pending;
  if (root_ != kEmptyChild) pending.push_back({root_, scene_->bounds(), 1});
  while (!pending.empty() && problems.size() < kMaxProblems) {
    const Item item = pending.back();
    pending.pop_back();
    if (item.depth > kBvhMaxDepth) problems.push_back("depth exceeds the traversal stack bound");
    if (item.ref & kLeafBit) {
      const std::uint32_t first = leaf_first_block(item.ref);
      const std::uint32_t count = leaf_block_count(item.ref);
      if (first + count > blocks_.size()) {
        problems.push_back("leaf block range out of bounds");
        continue;
      }
      for (std::uint32_t b = first; b < first + count; ++b) {
        for (int lane = 0; lane < 4; ++lane) {
          const std::uint32_t id = blocks_[b].prim_id[lane];
          if (id == kInvalidPrimId) continue;
          if (id >= seen.size()) {
            problems.push_back("leaf references primitive " + std::to_string(id) + " outside the scene");
            continue;
          }
          if (spatial_splits_) {
            // Spatial splits: a primitive may sit in several leaves, each holding a part of it, but once per leaf;
            // the leaf box bounds only the parts, so it must meet the primitive's box rather than contain it.
            const std::size_t before = std::size_t(b - first) * 4 + std::size_t(lane);  // lanes before this one
            bool repeated = false;
            for (std::size_t k = 0; k < before && !repeated; ++k) {
              repeated = blocks_[first + k / 4].prim_id[k % 4] == id;
            }
            if (repeated) problems.push_back("primitive " + std::to_string(id) + " appears twice in one leaf");
            seen[id] = 1;
            // (A primitive that became invalid after the build, refit since, has no bounds: never hit, not checked.)
            if (scene_->is_valid(id) && !item.box.overlaps(scene_->primitive_bounds(id))) {
              problems.push_back("primitive " + std::to_string(id) + " does not meet its leaf box");
            }
          } else {
            if (seen[id]++) problems.push_back("primitive " + std::to_string(id) + " referenced twice");
            if (!item.box.contains(scene_->primitive_bounds(id))) {
              problems.push_back("primitive " + std::to_string(id) + " lies outside its leaf box");
            }
          }
        }
      }
      continue;
    }
    if (item.ref >= nodes.size()) {
      problems.push_back("child reference " + std::to_string(item.ref) + " out of range");
      continue;
    }
    const Node<W>& node = nodes[item.ref];
    if (!child_order_is_permutation(node)) {
      problems.push_back("node " + std::to_string(item.ref) + ": a child order is not a permutation of its lanes");
    }
    for (int lane = 0; lane < W; ++lane) {
      if (node.child[lane] == kEmptyChild) {
        if (!child_bounds(node, lane).is_empty()) problems.push_back("unused child slot with a non-empty box");
        continue;
      }
      const AABB box = child_bounds(node, lane);
      if (!item.box.contains(box)) problems.push_back("child box outside its parent box");
      pending.push_back({node.child[lane], box, item.depth + 1});
    }
  }
  if (const auto stale = simd::first_stale_lane(blocks_, *scene_)) {
    problems.push_back("leaf copy of triangle " + std::to_string(*stale) + " differs from the scene");
  }
  report_unreferenced(*scene_, seen, "leaf", problems);
}

std::vector<std::string> WideBvh::validate() const {
  if (!scene_) return {"not built"};
  std::vector<std::string> problems;
  if (width_ == 8) {
    validate_nodes(nodes8_, problems);
  } else {
    validate_nodes(nodes4_, problems);
  }
  return problems;
}

}  // namespace rayaccel::wide
