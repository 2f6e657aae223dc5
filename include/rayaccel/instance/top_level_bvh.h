// TopLevelBvh: the binary BVH over instance world boxes, binned SAH (Wald 2007) with one instance per leaf (a leaf
// visit costs far more than a box test), traversed near child first with the slab test (Ize 2013).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rayaccel/bvh/build_tree.h"
#include "rayaccel/core/aabb.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/geometry/ray_box.h"

namespace rayaccel {

struct TopLevelNode {
  AABB box;                 ///< 24 bytes: bounds of every instance box below
  std::uint32_t first = 0;  ///< 4 bytes: leaf: first index into items; interior: left child (right is first + 1)
  std::uint32_t count = 0;  ///< 4 bytes: leaf: item count (>= 1); interior: 0
};
static_assert(sizeof(TopLevelNode) == 32, "TopLevelNode is 32 bytes");

class TopLevelBvh {
 public:
  /// Builds over boxes[i] for every i; empty boxes (instances of empty geometry) are left out. Rebuilding replaces
  /// the previous tree.
  void build(std::span<const AABB> boxes);
  /// Keeps the tree and recomputes every node's box bottom-up from `boxes` (the same count as built over, each
  /// empty exactly where it was). Throws Error otherwise.
  void refit(std::span<const AABB> boxes);

  /// Calls visit(item, t_far) for every item whose box (and every ancestor's) the ray's segment [ray.t_min, t_far]
  /// touches, nearer subtrees first. visit may shrink t_far (to the closest hit so far) and returns true to stop.
  template <class Visit>
  void traverse(const PreparedRay& ray, float& t_far, Visit&& visit) const {
    if (nodes_.empty() || !intersect_box(ray, nodes_[0].box, ray.t_min, t_far)) return;
    struct Entry {
      std::uint32_t node;
      float t_entry;
    };
    Entry stack[kBvhMaxDepth];
    int size = 0;
    std::uint32_t node = 0;
    for (;;) {
      const TopLevelNode& n = nodes_[node];
      if (n.count > 0) {
        for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
          if (visit(items_[i], t_far)) return;
        }
      } else {
        float t_left = 0.0f, t_right = 0.0f;
        const bool left = intersect_box(ray, nodes_[n.first].box, ray.t_min, t_far, &t_left);
        const bool right = intersect_box(ray, nodes_[n.first + 1].box, ray.t_min, t_far, &t_right);
        if (left && right) {
          const bool left_first = t_left <= t_right;
          stack[size++] = left_first ? Entry{n.first + 1, t_right} : Entry{n.first, t_left};
          node = left_first ? n.first : n.first + 1;
          continue;
        }
        if (left || right) {
          node = left ? n.first : n.first + 1;
          continue;
        }
      }
      do {
        if (size == 0) return;
        --size;
      } while (stack[size].t_entry > t_far);
      node = stack[size].node;
    }
  }

  std::uint32_t node_count() const { return static_cast<std::uint32_t>(nodes_.size()); }
  const std::vector<TopLevelNode>& nodes() const { return nodes_; }
  std::size_t memory_bytes() const;
  /// Checks that every child box lies inside its parent's, every item appears once and the depth is bounded; one
  /// line per violation. `boxes` are the boxes built over.
  std::vector<std::string> validate(std::span<const AABB> boxes) const;

 private:
  std::vector<TopLevelNode> nodes_;
  std::vector<std::uint32_t> items_;  // leaf order
  std::size_t built_count_ = 0;       // boxes.size() at the last build
};

}  // namespace rayaccel
