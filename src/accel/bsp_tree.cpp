// General BSP tree: build glue, build statistics, validate() and registration (traversal is in bsp_tree.h, the
// builder in bsp_tree_build.cpp, cell polytopes in bsp_tree_polytope.cpp).
#include "rayaccel/accel/bsp_tree.h"
#include "rayaccel/accel/split_tree_report.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/geometry/clip_polygon.h"

namespace rayaccel {

void BspTree::build(const Scene& scene) {
  const auto start = std::chrono::steady_clock::now();
  scene_ = &scene;
  data_ = build_bsp_tree(scene, options_);
  build_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

namespace {

struct PathPlane {
  Vec3 normal;
  double offset;
  bool below;
};

/// True when some part of the point set (a triangle when `polygon`, else box corners) lies in every half-space of
/// the path, each widened by `tolerance` (twice the builder's).
bool reaches_cell(std::vector<Vec3> points, bool polygon, const std::vector<PathPlane>& path, double tolerance) {
  for (const PathPlane& h : path) {
    const Vec3 n = h.below ? h.normal : -h.normal;
    const double d = (h.below ? h.offset : -h.offset) + tolerance;
    if (polygon) {
      std::vector<Vec3> out(clip_capacity(points.size()));
      const int k = clip_polygon_to_halfspace(points.data(), int(points.size()), n, d, out.data());
      if (k == 0) return false;
      out.resize(std::size_t(k));
      points = std::move(out);
    } else {
      bool any = false;
      for (const Vec3& p : points) any = any || double(n.x) * p.x + double(n.y) * p.y + double(n.z) * p.z <= d;
      if (!any) return false;
    }
  }
  return true;
}

}  // namespace

std::vector<BuildStatistic> BspTree::build_statistics() const {
  std::size_t leaves = 0, empty_leaves = 0;
  for (const BspNode& n : data_.nodes) {
    leaves += n.is_leaf() ? 1 : 0;
    empty_leaves += n.is_leaf() && n.prim_count() == 0 ? 1 : 0;
  }
  int max_depth = 0;
  std::vector<std::pair<std::uint32_t, int>> stack;
  if (!data_.nodes.empty()) stack.push_back({0, 0});
  while (!stack.empty()) {
    const auto [index, depth] = stack.back();
    stack.pop_back();
    max_depth = std::max(max_depth, depth);
    const BspNode& n = data_.nodes[index];
    if (n.is_leaf()) continue;
    stack.push_back({index + 1, depth + 1});
    stack.push_back({n.above_child(), depth + 1});
  }
  return split_tree_statistics({data_.nodes.size(), leaves, empty_leaves, max_depth, data_.prim_indices.size(),
                                data_.sah_cost, build_ms_},
                               scene_);
}

std::vector<std::string> BspTree::validate() const {
  if (!scene_) return {"not built"};
  ProblemList report;
  const std::size_t node_count = data_.nodes.size();
  const std::uint32_t prim_count = scene_->primitive_count();
  if (node_count == 0) {
    if (scene_->valid_count() != 0) report("no nodes, but the scene has valid primitives");
    return report.problems;
  }
  std::vector<std::uint8_t> referenced(prim_count, 0), reached(node_count, 0);
  std::vector<PathPlane> path;
  // Depth-first walk that keeps the planes from the root to the current node in `path`.
  struct Item {
    std::uint32_t node;
    int depth;
    PathPlane plane;  // the plane and side that lead into `node` (unused for the root)
  };
  std::vector<Item> stack{{0, 0, {}}};
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    path.resize(std::size_t(std::max(item.depth - 1, 0)));
    if (item.depth > 0) path.push_back(item.plane);
    const std::string where = "node " + std::to_string(item.node);
    if (item.node >= node_count) { report(where + ": child index out of range"); continue; }
    if (reached[item.node]) { report(where + ": reached twice"); continue; }
    reached[item.node] = 1;
    if (item.depth > data_.max_depth) report(where + ": depth " + std::to_string(item.depth) + " exceeds the limit");
    const BspNode& n = data_.nodes[item.node];
    if (!n.is_leaf()) {
      if (!is_finite(n.normal) || std::fabs(length(n.normal) - 1.0f) > 1e-5f || !std::isfinite(n.offset)) {
        report(where + ": split plane is not a unit normal with a finite offset");
      }
      if (n.above_child() <= item.node) report(where + ": child offsets out of order");
      stack.push_back({n.above_child(), item.depth + 1, {n.normal, n.offset, false}});
      stack.push_back({item.node + 1, item.depth + 1, {n.normal, n.offset, true}});
      continue;
    }
    if (std::size_t(n.prim_offset) + n.prim_count() > data_.prim_indices.size()) {
      report(where + ": leaf range out of the primitive-index array");
      continue;
    }
    for (std::uint32_t i = 0; i < n.prim_count(); ++i) {
      const std::uint32_t id = data_.prim_indices[n.prim_offset + i];
      if (id >= prim_count || !scene_->is_valid(id)) { report(where + ": bad primitive id"); continue; }
      referenced[id] = 1;
      std::array<Vec3, 8> hull;
      const int k = scene_->hull_points(id, hull);
      const bool polygon = scene_->kind() == PrimitiveKind::triangles;
      if (!reaches_cell(std::vector<Vec3>(hull.begin(), hull.begin() + k), polygon, path, 2.0 * data_.tolerance)) {
        report(where + ": primitive " + std::to_string(id) + " lies outside its cell");
      }
    }
  }
  report_unreached(reached, referenced, *scene_, report);
  return report.problems;
}

namespace {

BspTreeOptions parse_options(const Options& o) {
  BspTreeOptions b;
  const long long depth = o.get_int("max_depth");
  if (depth < 0 || depth > kMaxSplitTreeDepth) {
    throw Error("bsp: max_depth=" + o.get("max_depth") + " is outside [0, " + std::to_string(kMaxSplitTreeDepth) + "]");
  }
  b.max_depth = static_cast<int>(depth);
  const long long leaf = o.get_int("leaf_size");
  if (leaf < 1 || leaf > 1 << 20) throw Error("bsp: leaf_size=" + o.get("leaf_size") + " is outside [1, 2^20]");
  b.leaf_size = static_cast<int>(leaf);
  const long long exact = o.get_int("exact_threshold");
  if (exact < 0 || exact > 1 << 16) {
    throw Error("bsp: exact_threshold=" + o.get("exact_threshold") + " is outside [0, 65536]");
  }
  b.exact_threshold = static_cast<int>(exact);
  b.traversal_cost = static_cast<float>(o.get_real("traversal_cost"));
  b.intersection_cost = static_cast<float>(o.get_real("intersection_cost"));
  if (!(b.traversal_cost > 0.0f)) throw Error("bsp: traversal_cost=" + o.get("traversal_cost") + " must be > 0");
  if (!(b.intersection_cost > 0.0f)) {
    throw Error("bsp: intersection_cost=" + o.get("intersection_cost") + " must be > 0");
  }
  b.own_planes = o.get_bool("own_planes");
  return b;
}

}  // namespace

void register_bsp_tree(std::vector<AcceleratorInfo>& registry) {
  registry.push_back(
      {"bsp",
       "general BSP tree: arbitrary planes (own planes + 13 k-DOP directions), SAH over polytope cells (Ize 2008)",
       {{"max_depth", OptionType::integer, "0", "deepest leaf; 0 = round(8 + 1.3 log2 n)", {}},
        {"leaf_size", OptionType::integer, "1", "largest node made a leaf without trying splits", {}},
        {"traversal_cost", OptionType::real, "15", "SAH cost of one traversal step", {}},
        {"intersection_cost", OptionType::real, "20", "SAH cost of one primitive test", {}},
        {"exact_threshold", OptionType::integer, "12",
         "nodes with more references use 16 bins per direction and 8 sampled own planes", {}},
        {"own_planes", OptionType::boolean, "true", "also try the triangles' own supporting planes", {}}},
       {},
       [](const Options& o) { return std::make_unique<BspTree>(parse_options(o)); }});
}

}  // namespace rayaccel
