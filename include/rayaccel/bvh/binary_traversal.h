// The stack traversal of a binary BVH in its flat layout (first child next to its parent, second at node.index), the
// one copy that the float Bvh<BV> and the double DoubleBvh share: nearer child first, one deferred sibling per level.
#pragma once

#include <cstdint>

#include "rayaccel/bvh/build_tree.h"

namespace rayaccel {

/// Walks the tree from `nodes[start]` for a ray starting at `t_min`. The precision is the callers' (Real float or
/// double), given by three callbacks:
/// - `enter(node, t_far, &t_entry)`: whether the ray's segment [t_min, t_far] touches the node's volume (and where);
/// - `leaf(node)`: tests the leaf's primitives into the caller's hit; true ends the walk (an any-hit found);
/// - `cull_bound()`: the far bound that still admits a closer hit (it only shrinks while tracing).
/// Closest-hit (AnyHit false) descends into the nearer child first; any-hit into the first child.
template <bool AnyHit, class Real, class Node, class Enter, class Leaf, class CullBound, class Stats>
inline void traverse_binary_bvh(const Node* nodes, std::uint32_t start, Real t_min, Enter&& enter, Leaf&& leaf,
                                CullBound&& cull_bound, Stats& stats) {
  Real t_entry = t_min;
  stats.visit_node();
  if (!enter(nodes[start], cull_bound(), &t_entry)) return;
  struct Entry {
    std::uint32_t node;
    Real t_entry;
  };
  Entry stack[kBvhMaxDepth];  // one deferred sibling per level at most: depth <= kBvhMaxDepth (checked by validate)
  int top = 0;
  std::uint32_t current = start;
  for (;;) {
    const Node& node = nodes[current];
    if (node.count > 0) {
      if (leaf(node)) return;
    } else {
      const std::uint32_t first = current + 1;
      const std::uint32_t second = node.index;
      Real t_first = t_min, t_second = t_min;
      const Real t_far = cull_bound();
      const bool hit_first = enter(nodes[first], t_far, &t_first);
      const bool hit_second = enter(nodes[second], t_far, &t_second);
      if (hit_first && hit_second) {
        stats.visit_node();
        if (!AnyHit && t_second < t_first) {
          stack[top++] = {first, t_first};
          current = second;
        } else {
          stack[top++] = {second, t_second};
          current = first;
        }
        continue;
      }
      if (hit_first || hit_second) {
        stats.visit_node();
        current = hit_first ? first : second;
        continue;
      }
    }
    // Pop the nearest deferred node that can still hold a closer hit.
    for (;;) {
      if (top == 0) return;
      const Entry e = stack[--top];
      if (e.t_entry <= cull_bound()) {
        stats.visit_node();
        current = e.node;
        break;
      }
    }
  }
}

}  // namespace rayaccel
