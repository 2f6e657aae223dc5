// Octree build, incremental insertion and removal with split / merge, validation, statistics and registration
// (see octree.h).
#include "rayaccel/accel/octree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>

#include "rayaccel/accel/uniform_grid.h"
#include "rayaccel/core/error.h"

namespace rayaccel {

namespace {

std::string box_text(const AABB& b) {
  return "(" + std::to_string(b.lo.x) + ", " + std::to_string(b.lo.y) + ", " + std::to_string(b.lo.z) + ") - (" +
         std::to_string(b.hi.x) + ", " + std::to_string(b.hi.y) + ", " + std::to_string(b.hi.z) + ")";
}

}  // namespace

const OptionTable<OctreeOptions>& octree_option_table() {
  using O = OctreeOptions;
  static const OptionTable<O> table = [] {
    OptionTable<O> t("octree");
    t.integer("max_depth", &O::max_depth, 1, Octree::kMaxDepth, "levels below the root at most");
    t.integer("max_prims", &O::max_prims, 1, 1 << 20, "primitives per leaf before it splits");
    t.boolean("exact", &O::exact, "triangles: reference only leaves the triangle overlaps (SAT)");
    t.boolean("mailbox", &O::mailbox, "test a primitive spanning leaves once per ray");
    t.real("pad", &O::pad, RealRange::at_least(0.0), "grow the root box by pad * extent per side (room for insertions)");
    t.rule([](const O& o) {
      if (o.root_bounds && (o.root_bounds->is_empty() || !o.root_bounds->is_finite())) {
        throw Error("octree: root_bounds must be a finite, non-empty box");
      }
    });
    return t;
  }();
  return table;
}

Octree::Octree(OctreeOptions options) : options_(std::move(options)) { octree_option_table().check(options_); }

bool Octree::overlaps(std::uint32_t id, const AABB& box) const {
  return primitive_overlaps_cell(*scene_, id, box, pad_, exact_used_);
}

std::uint32_t Octree::new_list() {
  if (!free_lists_.empty()) {
    const std::uint32_t l = free_lists_.back();
    free_lists_.pop_back();
    return l;
  }
  lists_.emplace_back();
  return std::uint32_t(lists_.size() - 1);
}

std::uint32_t Octree::new_block() {
  if (!free_blocks_.empty()) {
    const std::uint32_t b = free_blocks_.back();
    free_blocks_.pop_back();
    return b;
  }
  nodes_.resize(nodes_.size() + 8);
  return std::uint32_t(nodes_.size() - 8);
}

void Octree::build(const Scene& scene) {
  scene_ = &scene;
  exact_used_ = options_.exact && scene.kind() == PrimitiveKind::triangles;
  nodes_.clear();
  lists_.clear();
  free_blocks_.clear();
  free_lists_.clear();
  active_.assign(scene.primitive_count(), 0);
  active_count_ = 0;
  removed_.clear();
  if (options_.root_bounds) {
    root_box_ = *options_.root_bounds;
    if (!root_box_.contains(scene.bounds())) {
      throw Error("octree: root_bounds " + box_text(root_box_) + " do not hold the scene bounds " +
                  box_text(scene.bounds()));
    }
  } else if (scene.bounds().is_empty()) {
    root_box_ = AABB({-1, -1, -1}, {1, 1, 1});
  } else {
    const AABB b = padded_scene_box(scene.bounds());
    const Vec3 grow = b.extent() * float(options_.pad);
    root_box_ = {b.lo - grow, b.hi + grow};
    if (!grid_box_is_finite(root_box_)) {
      // Wider than float's range (vertices near +-2e38): every float, one leaf, every primitive tested per ray.
      constexpr float kMax = std::numeric_limits<float>::max();
      root_box_ = AABB(Vec3{-kMax}, Vec3{kMax});
    }
  }
  pad_ = cell_padding(root_box_);
  nodes_.push_back({kLeaf, new_list()});
  std::vector<std::uint32_t>& root = lists_[nodes_[0].list];
  for (const PrimRef& ref : scene.build_references()) {
    root.push_back(ref.prim_id);
    active_[ref.prim_id] = 1;
  }
  active_count_ = std::uint32_t(root.size());
  split(0, root_box_, 0);
}

void Octree::split(std::uint32_t node, const AABB& box, int depth) {
  if (!may_split(box, depth)) return;
  const std::uint32_t list = nodes_[node].list;
  const std::size_t count = lists_[list].size();
  if (count <= std::size_t(options_.max_prims)) return;
  std::array<std::vector<std::uint32_t>, 8> parts;
  for (const std::uint32_t id : lists_[list]) {
    for (int c = 0; c < 8; ++c) {
      if (overlaps(id, child_box(box, c))) parts[c].push_back(id);
    }
  }
  std::array<std::size_t, 8> counts;
  for (int c = 0; c < 8; ++c) counts[c] = parts[c].size();
  if (!worth_splitting(counts, count)) return;
  const std::uint32_t first = new_block();
  lists_[list].clear();
  lists_[list].shrink_to_fit();
  free_lists_.push_back(list);
  nodes_[node] = {first, kLeaf};
  for (int c = 0; c < 8; ++c) {
    const std::uint32_t l = new_list();
    lists_[l] = std::move(parts[c]);
    nodes_[first + c] = {kLeaf, l};
  }
  for (int c = 0; c < 8; ++c) split(first + std::uint32_t(c), child_box(box, c), depth + 1);
}

void Octree::insert(std::uint32_t id) {
  if (!scene_) throw Error("octree: insert(" + std::to_string(id) + ") before build");
  if (id >= scene_->primitive_count()) {
    throw Error("octree: insert(" + std::to_string(id) + "): the scene has only " +
                std::to_string(scene_->primitive_count()) + " primitives");
  }
  if (!scene_->is_valid(id)) throw Error("octree: insert(" + std::to_string(id) + "): the primitive is invalid");
  if (is_active(id)) throw Error("octree: insert(" + std::to_string(id) + "): the primitive is already in the tree");
  if (!root_box_.contains(scene_->primitive_bounds(id))) {
    throw Error("octree: insert(" + std::to_string(id) + "): its bounds " + box_text(scene_->primitive_bounds(id)) +
                " are not inside the root box " + box_text(root_box_) +
                "; the root is never grown: build with option pad (or OctreeOptions::root_bounds) or rebuild");
  }
  if (active_.size() < scene_->primitive_count()) active_.resize(scene_->primitive_count(), 0);
  insert_into(0, root_box_, 0, id);
  active_[id] = 1;
  ++active_count_;
  if (id < removed_.size()) removed_[id] = 0;
}

void Octree::insert_into(std::uint32_t node, const AABB& box, int depth, std::uint32_t id) {
  if (!overlaps(id, box)) return;
  if (nodes_[node].first_child == kLeaf) {
    lists_[nodes_[node].list].push_back(id);
    split(node, box, depth);
    return;
  }
  const std::uint32_t first = nodes_[node].first_child;
  for (int c = 0; c < 8; ++c) insert_into(first + std::uint32_t(c), child_box(box, c), depth + 1, id);
}

UpdateKind Octree::update(const Scene& scene) {
  const std::vector<std::uint8_t> removed = scene_ == &scene ? removed_ : std::vector<std::uint8_t>{};
  build(scene);
  for (std::uint32_t id = 0; id < removed.size(); ++id) {
    if (removed[id] && is_active(id)) remove(id);
  }
  return UpdateKind::rebuilt;
}

void Octree::remove(std::uint32_t id) {
  if (!is_active(id)) throw Error("octree: remove(" + std::to_string(id) + "): the primitive is not in the tree");
  remove_from(0, root_box_, 0, id);
  active_[id] = 0;
  --active_count_;
  if (removed_.size() <= id) removed_.resize(std::size_t{id} + 1, 0);
  removed_[id] = 1;
}

void Octree::remove_from(std::uint32_t node, const AABB& box, int depth, std::uint32_t id) {
  if (!overlaps(id, box)) return;
  if (nodes_[node].first_child == kLeaf) {
    auto& list = lists_[nodes_[node].list];
    list.erase(std::remove(list.begin(), list.end(), id), list.end());
    // A leaf kept whole because splitting could not help (see worth_splitting) may be worth splitting now.
    split(node, box, depth);
    return;
  }
  const std::uint32_t first = nodes_[node].first_child;
  for (int c = 0; c < 8; ++c) remove_from(first + std::uint32_t(c), child_box(box, c), depth + 1, id);
  try_merge(node);
}

void Octree::try_merge(std::uint32_t node) {
  const std::uint32_t first = nodes_[node].first_child;
  std::vector<std::uint32_t> merged;
  for (int c = 0; c < 8; ++c) {
    const OctreeNode& child = nodes_[first + c];
    if (child.first_child != kLeaf) return;
    merged.insert(merged.end(), lists_[child.list].begin(), lists_[child.list].end());
  }
  std::sort(merged.begin(), merged.end());
  merged.erase(std::unique(merged.begin(), merged.end()), merged.end());
  if (merged.size() > std::size_t(options_.max_prims)) return;
  for (int c = 0; c < 8; ++c) {
    const std::uint32_t l = nodes_[first + c].list;
    lists_[l].clear();
    lists_[l].shrink_to_fit();
    free_lists_.push_back(l);
    nodes_[first + c] = {kLeaf, kLeaf};
  }
  free_blocks_.push_back(first);
  const std::uint32_t l = new_list();
  lists_[l] = std::move(merged);
  nodes_[node] = {kLeaf, l};
}

std::size_t Octree::memory_bytes() const {
  std::size_t bytes = sizeof(*this) + nodes_.capacity() * sizeof(OctreeNode) +
                      lists_.capacity() * sizeof(std::vector<std::uint32_t>) + active_.capacity() +
                      (free_blocks_.capacity() + free_lists_.capacity()) * sizeof(std::uint32_t);
  for (const auto& l : lists_) bytes += l.capacity() * sizeof(std::uint32_t);
  return bytes;
}

std::vector<BuildStatistic> Octree::build_statistics() const {
  std::size_t leaves = 0, empty = 0, references = 0, interior = 0;
  int max_depth = 0;
  std::vector<std::pair<std::uint32_t, int>> pending;
  if (!nodes_.empty()) pending.push_back({0, 0});
  while (!pending.empty()) {
    const auto [node, depth] = pending.back();
    pending.pop_back();
    max_depth = std::max(max_depth, depth);
    if (nodes_[node].first_child == kLeaf) {
      ++leaves;
      references += lists_[nodes_[node].list].size();
      empty += lists_[nodes_[node].list].empty();
      continue;
    }
    ++interior;
    for (std::uint32_t c = 0; c < 8; ++c) pending.push_back({nodes_[node].first_child + c, depth + 1});
  }
  return {{"interior_nodes", double(interior)},
          {"leaves", double(leaves)},
          {"empty_leaf_fraction", leaves ? double(empty) / double(leaves) : 0.0},
          {"max_depth", double(max_depth)},
          {"references", double(references)},
          {"references_per_primitive", active_count_ ? double(references) / active_count_ : 0.0}};
}

void Octree::validate_node(std::uint32_t node, const AABB& box, int depth, std::vector<std::uint8_t>& reached,
                           std::vector<std::uint8_t>& seen, std::vector<std::string>& problems) const {
  const std::string where = "node " + std::to_string(node) + ": ";
  if (node >= nodes_.size() || reached[node]) {
    problems.push_back(where + "out of range or reached twice");
    return;
  }
  reached[node] = 1;
  if (depth > options_.max_depth) problems.push_back(where + "deeper than max_depth");
  const OctreeNode& n = nodes_[node];
  if (n.first_child != kLeaf) {
    if (std::size_t(n.first_child) + 8 > nodes_.size()) {
      problems.push_back(where + "children out of range");
      return;
    }
    std::vector<std::uint32_t> merged;
    bool all_leaves = true;
    for (int c = 0; c < 8; ++c) {
      const OctreeNode& child = nodes_[n.first_child + c];
      all_leaves = all_leaves && child.first_child == kLeaf;
      if (child.first_child == kLeaf && child.list < lists_.size()) {
        merged.insert(merged.end(), lists_[child.list].begin(), lists_[child.list].end());
      }
    }
    std::sort(merged.begin(), merged.end());
    merged.erase(std::unique(merged.begin(), merged.end()), merged.end());
    if (all_leaves && merged.size() <= std::size_t(options_.max_prims)) {
      problems.push_back(where + "children hold " + std::to_string(merged.size()) + " primitives and should merge");
    }
    for (int c = 0; c < 8; ++c) validate_node(n.first_child + c, child_box(box, c), depth + 1, reached, seen, problems);
    return;
  }
  if (n.list >= lists_.size()) {
    problems.push_back(where + "leaf list out of range");
    return;
  }
  const auto& list = lists_[n.list];
  std::vector<std::uint32_t> sorted(list);
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) problems.push_back(where + "duplicate reference");
  for (const std::uint32_t id : list) {
    if (!is_active(id) || id >= scene_->primitive_count() || !scene_->is_valid(id)) {
      problems.push_back(where + "references inactive or invalid primitive " + std::to_string(id));
      continue;
    }
    seen[id] = 1;
    if (!primitive_overlaps_cell(*scene_, id, box, 2.0f * pad_, exact_used_)) {
      problems.push_back(where + "primitive " + std::to_string(id) + " does not overlap the leaf");
    }
  }
  if (list.size() > std::size_t(options_.max_prims) && may_split(box, depth)) {
    std::array<std::size_t, 8> counts{};
    for (int c = 0; c < 8; ++c) {
      for (const std::uint32_t id : list) counts[c] += is_active(id) && overlaps(id, child_box(box, c));
    }
    if (worth_splitting(counts, list.size())) problems.push_back(where + "leaf over max_prims should have split");
  }
}

std::vector<std::string> Octree::validate() const {
  if (!scene_) return {"not built"};
  std::vector<std::string> problems;
  if (nodes_.empty()) return {"no root node"};
  std::vector<std::uint8_t> reached(nodes_.size(), 0), seen(scene_->primitive_count(), 0);
  validate_node(0, root_box_, 0, reached, seen, problems);
  for (const std::uint32_t b : free_blocks_) {
    for (std::uint32_t c = 0; c < 8; ++c) {
      if (b + c >= nodes_.size() || reached[b + c]) problems.push_back("a released block is still in the tree");
    }
  }
  std::uint32_t active = 0;
  for (std::uint32_t id = 0; id < active_.size(); ++id) {
    if (!active_[id]) continue;
    ++active;
    if (id >= scene_->primitive_count() || !seen[id]) {
      problems.push_back("active primitive " + std::to_string(id) + " is in no leaf");
    } else if (!root_box_.contains(scene_->primitive_bounds(id))) {
      problems.push_back("active primitive " + std::to_string(id) + " is not inside the root box");
    }
  }
  if (active != active_count_) problems.push_back("active count is out of date");
  return problems;
}

void register_octree(std::vector<AcceleratorInfo>& registry) {
  registry.push_back(registry_entry<Octree>(
      octree_option_table(),
      "octree with parametric front-to-back traversal (Revelles et al. 2000), insert / remove after build",
      {"octree", "octree:exact=false", "octree:max_prims=2,max_depth=6"}));
}

}  // namespace rayaccel
