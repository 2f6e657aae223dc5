// Bvh<BV> construction steps: flattening the build tree into the depth-first node array, fitting volumes (AABB:
// bottom-up merge; other volumes: fitted to every hull point of the subtree, so each primitive lies inside every
// ancestor), refit after vertex motion (and update(), which refits or rebuilds), and the build statistics.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <type_traits>

#include "rayaccel/bvh/bvh.h"
#include "rayaccel/core/error.h"

namespace rayaccel {

template <BoundingVolume BV>
Bvh<BV>::Bvh(BvhOptions config) : config_(config) {
  bvh_option_table().check(config_);
}

template <BoundingVolume BV>
void Bvh<BV>::build(const Scene& scene) {
  const auto start = std::chrono::steady_clock::now();
  scene_ = &scene;
  const BuildTree tree = build_bvh_shape(scene, config_);
  flatten(tree);
  copy_triangles();
  fit_volumes();
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  compute_statistics(ms);
}

template <BoundingVolume BV>
void Bvh<BV>::flatten(const BuildTree& tree) {
  nodes_.clear();
  prim_ids_.clear();
  part_bounds_.clear();
  spatial_splits_ = tree.spatial_splits;
  depth_ = 0;
  if (tree.nodes.empty()) return;
  nodes_.reserve(tree.nodes.size());
  prim_ids_.reserve(tree.refs.size());
  if (tree.spatial_splits) part_bounds_.reserve(tree.refs.size());
  struct Item {
    std::uint32_t build_node;
    std::uint32_t parent;  ///< flat index of the parent whose second-child index this node fills; ~0u for none
    int depth;
  };
  std::vector<Item> pending{{0, ~0u, 1}};
  while (!pending.empty()) {
    const Item item = pending.back();
    pending.pop_back();
    const auto index = static_cast<std::uint32_t>(nodes_.size());
    if (item.parent != ~0u) nodes_[item.parent].index = index;
    depth_ = std::max(depth_, item.depth);
    const BuildNode& b = tree.nodes[item.build_node];
    Node node{};
    if (b.is_leaf()) {
      node.index = static_cast<std::uint32_t>(prim_ids_.size());
      node.count = b.count;
      for (std::uint32_t i = b.first; i < b.first + b.count; ++i) {
        prim_ids_.push_back(tree.refs[i].prim_id);
        if (tree.spatial_splits) part_bounds_.push_back(tree.refs[i].bounds);
      }
      nodes_.push_back(node);
    } else {
      nodes_.push_back(node);
      pending.push_back({b.first + 1, index, item.depth + 1});  // second child: its index is patched in when emitted
      pending.push_back({b.first, ~0u, item.depth + 1});        // first child: emitted next, right after this node
    }
  }
}

template <BoundingVolume BV>
void Bvh<BV>::copy_triangles() {
  triangles_.clear();
  if (scene_->kind() != PrimitiveKind::triangles) return;
  triangles_.resize(prim_ids_.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, prim_ids_.size(), 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) triangles_[i] = scene_->triangle(prim_ids_[i]);
  });
}

template <BoundingVolume BV>
int Bvh<BV>::slot_points(std::uint32_t slot, ClippedPolygon& out) const {
  const std::uint32_t id = prim_ids_[slot];
  if (!part_bounds_.empty() && scene_->kind() == PrimitiveKind::triangles) {
    return clip_triangle_polygon(scene_->triangle(id), part_bounds_[slot], out);
  }
  std::array<Vec3, 8> hull;
  const int n = scene_->hull_points(id, hull);
  for (int i = 0; i < n; ++i) out[i] = hull[i];
  return n;
}

template <BoundingVolume BV>
AABB Bvh<BV>::slot_box(std::uint32_t begin, std::uint32_t end) const {
  AABB box;
  if (part_bounds_.empty()) {
    // The box of a primitive's hull points is its bounds (triangle vertices, or the corners of the box).
    for (std::uint32_t s = begin; s < end; ++s) box.extend(scene_->primitive_bounds(prim_ids_[s]));
    return box;
  }
  ClippedPolygon points;
  for (std::uint32_t s = begin; s < end; ++s) {
    const int n = slot_points(s, points);
    for (int k = 0; k < n; ++k) box.extend(points[k]);
  }
  return box;
}

template <BoundingVolume BV>
void Bvh<BV>::fit_volumes() {
  const auto node_count = nodes_.size();
  if (node_count == 0) return;
  if constexpr (std::is_same_v<BV, AabbVolume>) {
    // Leaves in parallel; then, as children follow their parent in the array, one backward pass merges every
    // child into its parent.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, node_count, 4096), [&](const auto& range) {
      for (std::size_t i = range.begin(); i < range.end(); ++i) {
        Node& node = nodes_[i];
        if (node.is_leaf()) node.volume.box = slot_box(node.index, node.index + node.count);
      }
    });
    for (std::size_t i = node_count; i-- > 0;) {
      Node& node = nodes_[i];
      if (!node.is_leaf()) node.volume.box = merge(nodes_[i + 1].volume.box, nodes_[node.index].volume.box);
    }
  } else {
    // Every subtree's slots are one contiguous range (leaves are laid out depth-first), so each node is fitted
    // independently to the hull points of that range.
    std::vector<std::size_t> point_offset(prim_ids_.size() + 1, 0);
    std::vector<Vec3> points;
    points.reserve(prim_ids_.size() * 3);
    ClippedPolygon buffer;
    for (std::uint32_t s = 0; s < prim_ids_.size(); ++s) {
      const int n = slot_points(s, buffer);
      points.insert(points.end(), buffer.begin(), buffer.begin() + n);
      point_offset[s + 1] = points.size();
    }
    std::vector<std::array<std::uint32_t, 2>> slots(node_count);
    for (std::size_t i = node_count; i-- > 0;) {
      const Node& node = nodes_[i];
      slots[i] = node.is_leaf() ? std::array<std::uint32_t, 2>{node.index, node.index + node.count}
                                : std::array<std::uint32_t, 2>{slots[i + 1][0], slots[node.index][1]};
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, node_count, 64), [&](const auto& range) {
      for (std::size_t i = range.begin(); i < range.end(); ++i) {
        const std::size_t lo = point_offset[slots[i][0]], hi = point_offset[slots[i][1]];
        nodes_[i].volume = BV::fit(std::span<const Vec3>(points.data() + lo, hi - lo));
      }
    });
  }
}

template <BoundingVolume BV>
void Bvh<BV>::refit() {
  if (!scene_) throw Error("bvh refit: nothing was built");
  std::uint32_t max_id = 0;
  for (std::uint32_t id : prim_ids_) max_id = std::max(max_id, id);
  if (!prim_ids_.empty() && max_id >= scene_->primitive_count()) {
    throw Error("bvh refit: the scene now has " + std::to_string(scene_->primitive_count()) +
                " primitives, fewer than the tree refers to; rebuild instead");
  }
  part_bounds_.clear();
  copy_triangles();
  fit_volumes();
  compute_statistics(0.0);
}

template <BoundingVolume BV>
UpdateKind Bvh<BV>::update(const Scene& scene) {
  if (scene_ == &scene && detail::refit_covers_scene(scene, prim_ids_)) {
    refit();
    return UpdateKind::refitted;
  }
  build(scene);
  return UpdateKind::rebuilt;
}

template <BoundingVolume BV>
std::size_t Bvh<BV>::memory_bytes() const {
  return nodes_.size() * sizeof(Node) + prim_ids_.size() * sizeof(std::uint32_t) +
         triangles_.size() * sizeof(triangles_[0]) + part_bounds_.size() * sizeof(AABB);
}

template <BoundingVolume BV>
void Bvh<BV>::compute_statistics(double build_ms) {
  statistics_.clear();
  std::size_t leaf_count = 0;
  double sah = 0.0, tightness = 0.0;
  std::size_t tightness_count = 0;
  if (!nodes_.empty()) {
    // Box of each node's contents, to compare the fitted volume's area with (an AABB volume is that box).
    std::vector<AABB> content(nodes_.size());
    for (std::size_t i = nodes_.size(); i-- > 0;) {
      const Node& node = nodes_[i];
      if (std::is_same_v<BV, AabbVolume>) {
        content[i] = node.volume.bounds();
      } else if (node.is_leaf()) {
        content[i] = slot_box(node.index, node.index + node.count);
      } else {
        content[i] = merge(content[i + 1], content[node.index]);
      }
    }
    const double root_area = nodes_[0].volume.surface_area();
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      const Node& node = nodes_[i];
      const double area = node.volume.surface_area();
      const double relative = root_area > 0.0 ? area / root_area : 1.0;
      if (node.is_leaf()) {
        ++leaf_count;
        sah += config_.costs.intersection * node.count * relative;
      } else {
        sah += config_.costs.traversal * relative;
      }
      const double box_area = content[i].surface_area();
      if (box_area > 0.0) {
        tightness += area / box_area;
        ++tightness_count;
      }
    }
  }
  std::uint32_t valid = 0;
  for (std::uint32_t id = 0; id < scene_->primitive_count(); ++id) valid += scene_->is_valid(id) ? 1 : 0;
  statistics_ = {
      {"sah_cost", sah},
      {"sah_traversal_cost", config_.costs.traversal},
      {"sah_intersection_cost", config_.costs.intersection},
      {"node_count", static_cast<double>(nodes_.size())},
      {"leaf_count", static_cast<double>(leaf_count)},
      {"depth", static_cast<double>(depth_)},
      {"references_per_primitive", valid > 0 ? static_cast<double>(prim_ids_.size()) / valid : 0.0},
      {"volume_tightness", tightness_count > 0 ? tightness / tightness_count : 1.0},
      {"build_ms", build_ms},
  };
}

}  // namespace rayaccel
