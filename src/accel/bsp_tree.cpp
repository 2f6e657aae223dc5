// General BSP tree: build glue, build statistics, validate() and registration (traversal is in bsp_tree.h, the
// builder in bsp_tree_build.cpp, cell polytopes in bsp_tree_polytope.cpp).
#include "rayaccel/accel/bsp_tree.h"
#include "rayaccel/accel/split_tree_report.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <string>

#include "rayaccel/accel/split_tree_options.h"
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

// Option table, checked constructor and registry entry: the registration every structure has (kd_tree.cpp's reads
// alike), each over its own options.
const OptionTable<BspTreeOptions>& bsp_tree_option_table() {
  using O = BspTreeOptions;
  static const OptionTable<O> table = [] {
    OptionTable<O> t("bsp");
    add_split_tree_options(t, "largest node made a leaf without trying splits", "SAH cost of one traversal step",
                           "SAH cost of one primitive test");
    t.integer("exact_threshold", &O::exact_threshold, 0, 1 << 16,
              "nodes with more references use 16 bins per direction and 8 sampled own planes");
    t.boolean("own_planes", &O::own_planes, "also try the triangles' own supporting planes");
    return t;
  }();
  return table;
}

BspTree::BspTree(BspTreeOptions options) : options_(options) { bsp_tree_option_table().check(options_); }

void register_bsp_tree(std::vector<AcceleratorInfo>& registry) {
  registry.push_back(registry_entry<BspTree>(
      bsp_tree_option_table(),
      "general BSP tree: arbitrary planes (own planes + 13 k-DOP directions), SAH over polytope cells (Ize 2008)",
      {}));
}

}  // namespace rayaccel
