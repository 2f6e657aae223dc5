// Bvh<BV>::validate(): the tree's invariants, checked from scratch (after the idea of obvhs's validate): node
// indices in range, every node reached once, depth within the traversal stack, leaf sizes, every valid primitive
// referenced exactly once (SBVH: at least once), and every primitive part inside the volume of each ancestor.
#pragma once

#include <string>

#include "rayaccel/bvh/bvh.h"

namespace rayaccel {

template <BoundingVolume BV>
std::vector<std::string> Bvh<BV>::validate() const {
  std::vector<std::string> problems;
  constexpr std::size_t kMaxReports = 8;  // per kind of problem, so one broken subtree does not flood the report
  std::size_t reports = 0;
  auto report = [&](const std::string& line) {
    if (reports++ < kMaxReports) problems.push_back(line);
  };
  if (!scene_) return {"not built"};
  const auto node_count = static_cast<std::uint32_t>(nodes_.size());
  const auto slot_count = static_cast<std::uint32_t>(prim_ids_.size());
  std::uint32_t valid = 0;
  for (std::uint32_t id = 0; id < scene_->primitive_count(); ++id) valid += scene_->is_valid(id) ? 1 : 0;
  if (node_count == 0) {
    if (valid > 0) problems.push_back("empty tree but the scene has " + std::to_string(valid) + " valid primitives");
    if (slot_count > 0) problems.push_back("empty tree but " + std::to_string(slot_count) + " primitive slots");
    return problems;
  }
  if (!triangles_.empty() && triangles_.size() != slot_count) problems.push_back("triangle copy size differs");
  if (!part_bounds_.empty() && part_bounds_.size() != slot_count) problems.push_back("part bounds size differs");
  if (!problems.empty()) return problems;

  // Structure: walk from the root, count visits per node and per slot, and record subtree slot ranges.
  std::vector<std::uint32_t> node_visits(node_count, 0), slot_visits(slot_count, 0);
  std::vector<std::array<std::uint32_t, 2>> slot_range(node_count, {0, 0});
  std::vector<std::array<std::uint32_t, 2>> pending{{0, 1}};  // {node, depth}
  int max_depth = 0;
  bool structure_ok = true;
  while (!pending.empty()) {
    const auto [i, depth] = pending.back();
    pending.pop_back();
    max_depth = std::max(max_depth, static_cast<int>(depth));
    if (++node_visits[i] > 1) {
      report("node " + std::to_string(i) + " is reached more than once");
      structure_ok = false;
      continue;
    }
    const Node& node = nodes_[i];
    if (node.is_leaf()) {
      if (node.count > config_.max_leaf_size) {
        report("leaf " + std::to_string(i) + " holds " + std::to_string(node.count) + " primitives, more than " +
               std::to_string(config_.max_leaf_size));
      }
      if (std::uint64_t{node.index} + node.count > slot_count) {
        report("leaf " + std::to_string(i) + " slots [" + std::to_string(node.index) + ", +" +
               std::to_string(node.count) + ") are out of range");
        structure_ok = false;
        continue;
      }
      for (std::uint32_t s = node.index; s < node.index + node.count; ++s) ++slot_visits[s];
    } else if (i + 1 >= node_count || node.index <= i + 1 || node.index >= node_count) {
      report("interior node " + std::to_string(i) + " has child indices " + std::to_string(i + 1) + ", " +
             std::to_string(node.index) + " out of range (node count " + std::to_string(node_count) + ")");
      structure_ok = false;
    } else if (depth >= static_cast<std::uint32_t>(kBvhMaxDepth)) {
      report("node " + std::to_string(i) + " has children deeper than the stack bound " +
             std::to_string(kBvhMaxDepth));
      structure_ok = false;
    } else {
      pending.push_back({node.index, depth + 1});
      pending.push_back({i + 1, depth + 1});
    }
  }
  if (max_depth != depth_) report("recorded depth " + std::to_string(depth_) + " but the tree has " +
                                  std::to_string(max_depth) + " levels");
  for (std::uint32_t i = 0; i < node_count; ++i) {
    if (node_visits[i] == 0) { report("node " + std::to_string(i) + " is unreachable"); structure_ok = false; }
  }
  for (std::uint32_t s = 0; s < slot_count; ++s) {
    if (slot_visits[s] != 1) {
      report("primitive slot " + std::to_string(s) + " belongs to " + std::to_string(slot_visits[s]) + " leaves");
      structure_ok = false;
    }
  }

  // References: ids in range and valid, each valid primitive once (SBVH: at least once).
  reports = 0;
  std::vector<std::uint32_t> refs_per_prim(scene_->primitive_count(), 0);
  for (std::uint32_t s = 0; s < slot_count; ++s) {
    const std::uint32_t id = prim_ids_[s];
    if (id >= scene_->primitive_count()) {
      report("slot " + std::to_string(s) + " refers to primitive " + std::to_string(id) + ", which is out of range");
      structure_ok = false;
      continue;
    }
    // A primitive that became invalid after the build (a vertex moved to NaN, then refit) stays in its slot, never
    // hit (its copy and the scene's are zero); it has no bounds to check.
    if (!scene_->is_valid(id)) continue;
    ++refs_per_prim[id];
    if (!triangles_.empty() && triangles_[s] != scene_->triangle(id)) {
      report("slot " + std::to_string(s) + " holds a stale copy of triangle " + std::to_string(id));
    }
    if (!part_bounds_.empty() && !widen_for_clipping(scene_->primitive_bounds(id)).contains(part_bounds_[s])) {
      report("slot " + std::to_string(s) + ": the clipped part of primitive " + std::to_string(id) +
             " lies outside the primitive's bounds");
    }
  }
  const bool spatial = spatial_splits_;
  for (std::uint32_t id = 0; id < scene_->primitive_count(); ++id) {
    if (!scene_->is_valid(id)) continue;
    if (refs_per_prim[id] == 0 || (!spatial && refs_per_prim[id] > 1)) {
      report("primitive " + std::to_string(id) + " is referenced " + std::to_string(refs_per_prim[id]) +
             (spatial ? " times (expected at least once)" : " times (expected exactly once)"));
    }
  }
  if (!structure_ok) return problems;

  // Volumes: each node's volume holds every point of every primitive part in its subtree.
  reports = 0;
  for (std::uint32_t i = node_count; i-- > 0;) {
    const Node& node = nodes_[i];
    slot_range[i] = node.is_leaf() ? std::array<std::uint32_t, 2>{node.index, node.index + node.count}
                                   : std::array<std::uint32_t, 2>{slot_range[i + 1][0], slot_range[node.index][1]};
  }
  ClippedPolygon points;
  for (std::uint32_t i = 0; i < node_count; ++i) {
    bool inside = true;
    for (std::uint32_t s = slot_range[i][0]; s < slot_range[i][1] && inside; ++s) {
      if (!scene_->is_valid(prim_ids_[s])) continue;
      const int n = slot_points(s, points);
      if (n == 0 && !part_bounds_.empty()) {
        report("slot " + std::to_string(s) + ": the clipped part of primitive " + std::to_string(prim_ids_[s]) +
               " is empty");
      }
      for (int k = 0; k < n && inside; ++k) inside = nodes_[i].volume.contains(points[k]);
      if (!inside) {
        report(std::string(nodes_[i].is_leaf() ? "leaf " : "node ") + std::to_string(i) + ": primitive " +
               std::to_string(prim_ids_[s]) + (part_bounds_.empty() ? "" : " (its clipped part)") + " is outside the volume");
      }
    }
  }
  return problems;
}

}  // namespace rayaccel
