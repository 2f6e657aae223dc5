// Member definitions of Bvh<BV> for the queries beyond the first hit: every leaf the ray's whole interval enters (all
// hits), and a branch-and-bound closest-point search that descends into the nearer child first and skips any node
// whose box lies beyond the best distance so far (the classic nearest-neighbour search over a hierarchy).
#pragma once

#include "rayaccel/bvh/bvh.h"

namespace rayaccel {

template <BoundingVolume BV>
void Bvh<BV>::find_crossings(HitList& list) const {
  if (nodes_.empty()) return;
  detail::require_triangle_scene(*scene_, "all-hits");
  const PreparedRay& ray = list.ray();
  const typename BV::RayContext context = BV::prepare(ray);
  // Culled as the closest-hit traversal culls against a hit at t_max: a triangle whose computed t is within t_max
  // lies in a volume the widened bound reaches, so the same triangles are found as by brute force.
  const float t_far = bvh_cull_bound(Hit::begin(ray).t);
  std::uint32_t stack[kBvhMaxDepth + 1];  // both children pushed per level popped: at most depth + 1 entries
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    float t_entry = ray.t_min;
    if (!node.volume.intersect(context, ray.t_min, t_far, &t_entry)) continue;
    if (node.is_leaf()) {
      for (std::uint32_t slot = node.index, end = node.index + node.count; slot < end; ++slot) {
        const auto& v = triangles_[slot];
        list.test(prim_ids_[slot], v[0], v[1], v[2]);
      }
    } else {
      stack[top++] = node.index;
      stack[top++] = static_cast<std::uint32_t>(&node - nodes_.data()) + 1;
    }
  }
}

template <BoundingVolume BV>
void Bvh<BV>::find_closest_point(ClosestPointSearch& search) const {
  if (nodes_.empty()) return;
  detail::require_triangle_scene(*scene_, "closest-point");
  struct Entry {
    std::uint32_t node;
    double bound;  ///< lower bound on the squared distance to anything in the node
  };
  Entry stack[kBvhMaxDepth + 1];
  int top = 0;
  stack[top++] = {0, search.box_lower_bound(nodes_[0].volume.bounds())};
  while (top > 0) {
    const Entry e = stack[--top];
    if (!search.may_improve(e.bound)) continue;
    const Node& node = nodes_[e.node];
    if (node.is_leaf()) {
      for (std::uint32_t slot = node.index, end = node.index + node.count; slot < end; ++slot) {
        const auto& v = triangles_[slot];
        search.test(prim_ids_[slot], v[0], v[1], v[2]);
      }
      continue;
    }
    Entry near{e.node + 1, search.box_lower_bound(nodes_[e.node + 1].volume.bounds())};
    Entry far{node.index, search.box_lower_bound(nodes_[node.index].volume.bounds())};
    if (far.bound < near.bound) std::swap(near, far);
    if (search.may_improve(far.bound)) stack[top++] = far;
    if (search.may_improve(near.bound)) stack[top++] = near;
  }
}

}  // namespace rayaccel
