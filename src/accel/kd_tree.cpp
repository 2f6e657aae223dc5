// kd-tree: build dispatch, the Triangle4 copy of the leaves, build statistics, validate() and registration (traversal
// is in kd_tree.h, builders in kd_tree_build.cpp).
#include "rayaccel/accel/kd_tree.h"
#include "rayaccel/accel/split_tree_report.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "rayaccel/accel/split_tree_options.h"
#include "rayaccel/core/error.h"
#include "rayaccel/geometry/clip_polygon.h"

namespace rayaccel {

namespace {

/// The ClipToCell of a scene: triangles are clipped exactly, other primitives by their boxes.
ClipToCell scene_clipper(const Scene& scene) {
  if (scene.kind() == PrimitiveKind::triangles) {
    return [&scene](std::uint32_t id, const AABB& cell) {
      const auto& t = scene.triangle(id);
      return clip_triangle_to_box(t[0], t[1], t[2], cell);
    };
  }
  return [&scene](std::uint32_t id, const AABB& cell) {
    const AABB b = intersection(scene.primitive_bounds(id), cell);
    return b.is_empty() ? AABB{} : b;
  };
}

/// A cell grown by twice the builders' clipping margin at the root: builders clip each reference against some
/// ancestor cell widened by 2^-20 of that cell's coordinate magnitude (widen_for_clipping), never more than the
/// root's, so a reference may legitimately reach only that margin around its leaf; anything farther is an error.
AABB loose_cell(const AABB& cell, const AABB& root) {
  AABB out = cell;
  for (int a = 0; a < 3; ++a) {
    const float pad = std::fmax(std::fabs(root.lo[a]), std::fabs(root.hi[a])) * 0x1p-19f + 0x1p-125f;
    out.lo[a] -= pad;
    out.hi[a] += pad;
  }
  return out;
}

/// Visits every node with its cell and depth, depth first.
template <class F>
void for_each_node(const KdTreeData& data, F&& f) {
  if (data.nodes.empty()) return;
  struct Item {
    std::uint32_t node;
    AABB cell;
    int depth;
  };
  std::vector<Item> stack{{0, data.bounds, 0}};
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    if (!f(item.node, item.cell, item.depth)) continue;
    const KdNode& n = data.nodes[item.node];
    if (n.is_leaf()) continue;
    AABB below = item.cell, above = item.cell;
    below.hi[n.axis()] = n.split;
    above.lo[n.axis()] = n.split;
    stack.push_back({n.above_child(), above, item.depth + 1});
    stack.push_back({item.node + 1, below, item.depth + 1});
  }
}

}  // namespace

void KdTree::build(const Scene& scene) {
  const auto start = std::chrono::steady_clock::now();
  scene_ = &scene;
  const PrimRefs refs = scene.build_references();
  const ClipToCell clip = scene_clipper(scene);
  KdTreeOptions o = options_;
  if (scene.kind() != PrimitiveKind::triangles) o.block_size = 1;  // tested one by one
  data_ = o.builder == KdTreeOptions::Builder::sah ? build_kd_tree_sah(refs, o, clip)
                                                   : build_kd_tree_median(refs, o, clip);
  build_blocks(scene);
  build_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void KdTree::build_blocks(const Scene& scene) {
  block_first_.clear();
  blocks_.clear();
  isa_ = simd::Isa::sse2;
  if (scene.kind() != PrimitiveKind::triangles || data_.nodes.empty()) return;
  block_first_.resize(data_.nodes.size() + 1);
  for (std::size_t i = 0; i < data_.nodes.size(); ++i) {
    block_first_[i] = static_cast<std::uint32_t>(blocks_.size());
    const KdNode& n = data_.nodes[i];
    if (!n.is_leaf()) continue;
    simd::pack_triangle_blocks(
        scene, std::span<const std::uint32_t>(data_.prim_indices.data() + n.prim_offset, n.prim_count()), blocks_);
  }
  block_first_.back() = static_cast<std::uint32_t>(blocks_.size());
  blocks_.shrink_to_fit();
  isa_ = simd::best_isa(kMaxIsa);
}

std::vector<BuildStatistic> KdTree::build_statistics() const {
  std::size_t leaves = 0, empty_leaves = 0;
  int max_depth = 0;
  double sah = 0.0;
  const double root_area = data_.bounds.surface_area();
  for_each_node(data_, [&](std::uint32_t index, const AABB& cell, int depth) {
    const KdNode& n = data_.nodes[index];
    max_depth = std::max(max_depth, depth);
    const double p = root_area > 0.0 ? cell.surface_area() / root_area : 1.0;
    if (n.is_leaf()) {
      ++leaves;
      empty_leaves += n.prim_count() == 0 ? 1 : 0;
      sah += p * kd_leaf_cost(blocks_.empty() ? KdTreeOptions{.block_size = 1} : options_, n.prim_count());
    } else {
      sah += p * options_.traversal_cost;
    }
    return true;
  });
  std::vector<BuildStatistic> stats = split_tree_statistics(
      {data_.nodes.size(), leaves, empty_leaves, max_depth, data_.prim_indices.size(), sah, build_ms_}, scene_);
  if (!blocks_.empty()) {
    std::size_t used = 0;
    for (const auto& b : blocks_) {
      for (std::uint32_t id : b.prim_id) used += id != kInvalidPrimId ? 1 : 0;
    }
    stats.push_back({"triangle4_blocks", double(blocks_.size())});
    stats.push_back({"block_fill", double(used) / (4.0 * double(blocks_.size()))});
  }
  return stats;
}

std::vector<std::string> KdTree::validate() const {
  if (!scene_) return {"not built"};
  ProblemList report;
  const std::size_t node_count = data_.nodes.size();
  const std::uint32_t prim_count = scene_->primitive_count();
  if (node_count == 0) {
    if (scene_->valid_count() != 0) report("no nodes, but the scene has valid primitives");
    return report.problems;
  }
  const ClipToCell clip = scene_clipper(*scene_);
  const int depth_limit = kd_tree_max_depth(options_, scene_->valid_count());
  std::vector<std::uint8_t> referenced(prim_count, 0);
  std::vector<std::uint8_t> reached(node_count, 0);
  for_each_node(data_, [&](std::uint32_t index, const AABB& cell, int depth) {
    const std::string where = "node " + std::to_string(index);
    if (index >= node_count) { report(where + ": child index out of range"); return false; }
    if (reached[index]) { report(where + ": reached twice"); return false; }
    reached[index] = 1;
    if (depth > depth_limit) report(where + ": depth " + std::to_string(depth) + " exceeds the limit");
    const KdNode& n = data_.nodes[index];
    if (!n.is_leaf()) {
      const int a = n.axis();
      if (!(n.split >= cell.lo[a] && n.split <= cell.hi[a])) report(where + ": split position outside its cell");
      if (index + 1 >= node_count || n.above_child() <= index) report(where + ": child offsets out of order");
      return true;
    }
    if (std::size_t(n.prim_offset) + n.prim_count() > data_.prim_indices.size()) {
      report(where + ": leaf range out of the primitive-index array");
      return false;
    }
    for (std::uint32_t i = 0; i < n.prim_count(); ++i) {
      const std::uint32_t id = data_.prim_indices[n.prim_offset + i];
      if (id >= prim_count || !scene_->is_valid(id)) { report(where + ": bad primitive id"); continue; }
      referenced[id] = 1;
      if (clip(id, loose_cell(cell, data_.bounds)).is_empty()) {
        report(where + ": primitive " + std::to_string(id) + " does not reach its cell");
      }
    }
    return true;
  });
  report_unreached(reached, referenced, *scene_, report);
  if (!block_first_.empty()) validate_blocks(report);
  return report.problems;
}

void KdTree::validate_blocks(ProblemList& report) const {
  if (block_first_.size() != data_.nodes.size() + 1 || block_first_.back() != blocks_.size()) {
    report("Triangle4 block table does not match the nodes");
    return;
  }
  for (std::size_t i = 0; i < data_.nodes.size(); ++i) {
    const KdNode& n = data_.nodes[i];
    const std::uint32_t first = block_first_[i], last = block_first_[i + 1];
    if (last < first || (!n.is_leaf() && last != first)) {
      report("node " + std::to_string(i) + ": bad Triangle4 block range");
      return;
    }
    if (!n.is_leaf()) continue;
    // The blocks must hold the leaf's references in order, copied exactly.
    std::vector<std::uint32_t> expected;
    for (std::uint32_t k = 0; k < n.prim_count(); ++k) {
      const std::size_t at = std::size_t(n.prim_offset) + k;
      if (at >= data_.prim_indices.size()) break;
      const std::uint32_t id = data_.prim_indices[at];
      if (id < scene_->primitive_count()) expected.push_back(id);
    }
    std::size_t k = 0;
    bool ok = last - first == (expected.size() + 3) / 4;
    simd::for_each_block_id(blocks_.data() + first, last - first, [&](const simd::Triangle4& b, int lane) {
      ok = ok && k < expected.size() && expected[k++] == b.prim_id[lane];
    });
    ok = ok && k == expected.size() && !simd::first_stale_lane({blocks_.data() + first, last - first}, *scene_);
    if (!ok) report("node " + std::to_string(i) + ": Triangle4 blocks differ from the leaf");
  }
}

const OptionTable<KdTreeOptions>& kd_tree_option_table() {
  using O = KdTreeOptions;
  static const OptionTable<O> table = [] {
    OptionTable<O> t("kdtree");
    t.choice("builder", &O::builder, {{"median", O::Builder::median}, {"sah", O::Builder::sah}},
             "median: median centroid, axes cycling; sah: Wald & Havran sweep");
    add_split_tree_options(t, "median builder: largest node made a leaf", "SAH cost of one traversal step (K_T)",
                           "SAH cost of one primitive test or Triangle4 block (K_I)");
    t.real("empty_bonus", &O::empty_bonus, {0.0, 1.0, false, true},
           "SAH: cost fraction saved by cutting off an empty cell");
    t.integer("block_size", &O::block_size, 1, 64,
              "SAH: K_I per started block of this many triangles (leaves are Triangle4 blocks); 1 = per triangle");
    t.boolean("mailbox", &O::mailbox, "skip primitives the ray already tested (8-entry mailbox)");
    return t;
  }();
  return table;
}

KdTree::KdTree(KdTreeOptions options) : options_(options) { kd_tree_option_table().check(options_); }

void register_kd_tree(std::vector<AcceleratorInfo>& registry) {
  registry.push_back(registry_entry<KdTree>(
      kd_tree_option_table(),
      "kd-tree: median or O(N log N) SAH build with perfect splits (Wald & Havran 2006), 8-byte nodes",
      {"kdtree:builder=median", "kdtree:builder=sah", "kdtree:builder=sah,mailbox=true"}));
}

}  // namespace rayaccel
