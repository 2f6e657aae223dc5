// Wide BVH: the build (optional pre-splitting, the binary SAH tree, its collapse and leaf packing), memory and
// statistics. The steps live in wide_collapse.cpp, wide_leaves.cpp, wide_validate.cpp; traversal in wide_bvh.h and
// wide_bvh_packets.cpp.
#include "rayaccel/wide/wide_bvh.h"

#include <string>

#include "rayaccel/bvh/presplit.h"
#include "rayaccel/bvh/reinsertion.h"
#include "rayaccel/bvh/sbvh_builder.h"
#include "rayaccel/core/error.h"

namespace rayaccel::wide {

void WideBvh::build(const Scene& scene) {
  // Computed for every triangle scene (it is cheap: BENCHMARKS.md), so the statistic is reported whatever the options.
  const bool triangles = scene.kind() == PrimitiveKind::triangles;
  const double potential = triangles ? presplit_potential(scene) : 0.0;
  BuildTree tree;
  std::uint32_t split_triangles = 0;
  if (config_.spatial > 0.0f && triangles) {
    const SbvhOptions sbvh{.max_leaf_size = config_.binary.max_leaf_size,
                           .costs = config_.binary.costs,
                           .bin_count = config_.binary.bin_count,
                           .max_growth = 1.0f + config_.spatial,
                           .block_size = config_.binary.block_size};
    tree = build_sbvh(scene, sbvh);
  } else if (config_.presplit > 0.0f && triangles && potential >= config_.presplit_threshold) {
    PresplitResult presplit = presplit_references(scene, {.fraction = config_.presplit});
    tree = build_binned_sah(std::move(presplit.refs), config_.binary);
    tree.spatial_splits = true;
    split_triangles = presplit.split_triangles;
  } else {
    tree = build_binned_sah(scene.build_references(), config_.binary);
  }
  if (config_.reinsert > 0) {
    reinsert_nodes(tree, {.costs = config_.binary.costs,
                          .block_size = config_.binary.block_size,
                          .max_batches = config_.reinsert});
  }
  build_from(scene, tree);
  split_triangles_ = split_triangles;
  presplit_potential_ = potential;
}

void WideBvh::build_from(const Scene& scene, const BuildTree& tree) {
  scene_ = &scene;
  spatial_splits_ = tree.spatial_splits;
  references_ = static_cast<std::uint32_t>(tree.refs.size());
  split_triangles_ = 0;
  presplit_potential_ = 0.0;  // build() sets it; a tree built elsewhere was not chosen by it
  dropped_repeats_ = 0;
  triangles_ = scene.kind() == PrimitiveKind::triangles;
  select_kernels(config_.width);  // a CPU without AVX2 gets four-wide nodes, also for width=8
  nodes4_.clear();
  nodes8_.clear();
  blocks_.clear();
  block_count_ = 0;
  depth_ = 0;
  binary_bounds_ = binary_node_bounds(tree);
  pending_leaves_.clear();
  pending_ids_.clear();
  pending_ids_.reserve(tree.refs.size());
  // Room for the nodes without regrowing: every wide node takes at least one binary interior node, so their count
  // bounds it. Full eight-wide nodes would need a seventh of that, but the shared scenes need 1/3.5 to 1/3.3 (many
  // children are leaves, which are not opened), so the old estimate of a seventh always regrew, copying the whole
  // array into fresh pages. Capacity that is never written is never given pages.
  // Leaf blocks are counted during the collapse and allocated once after it.
  const std::size_t interior = tree.nodes.size() / 2 + 1;
  if (width_ == 8) {
    nodes8_.reserve(interior);
  } else {
    nodes4_.reserve(interior);
  }
  if (config_.collapse == WideCollapse::sah && !tree.nodes.empty()) {
    collapse_plan_.resize(tree.nodes.size());
    float root_costs[8];
    plan_collapse(tree, 0, root_costs);
  }
  if (tree.nodes.empty()) {
    root_ = kEmptyChild;
  } else {
    root_ = width_ == 8 ? emit<8>(tree, 0, 1, nodes8_) : emit<4>(tree, 0, 1, nodes4_);
  }
  blocks_.resize(block_count_);  // uninitialized: fill_leaves() writes every lane of every block, in parallel
  fill_leaves();
  binary_bounds_ = {};
  collapse_plan_ = {};
  pending_leaves_ = {};
  pending_ids_ = {};
  if (depth_ > kBvhMaxDepth) {
    throw Error("wide BVH: tree depth " + std::to_string(depth_) + " exceeds the traversal stack bound");
  }
}

bool WideBvh::runs_eight_wide() { return simd::best_isa(simd::Isa::avx2) != simd::Isa::sse2; }

void WideBvh::select_kernels(int width) {
  width_ = (width == 8 || width == 0) && runs_eight_wide() ? 8 : 4;
  isa_ = width_ == 8 ? simd::best_isa(config_.isa == WideIsa::avx2 ? simd::Isa::avx2 : simd::Isa::avx512)
                     : simd::Isa::sse2;
}


namespace {

/// SAH cost of a wide tree relative to its root box's area: `traversal` per node visit, `intersection` per leaf
/// block, as the binary build costs its tree (the figure collapse=sah minimises, up to repeated pieces).
template <int W>
double wide_sah_cost(const NodeArray<W>& nodes, std::uint32_t root, const SahCosts& costs) {
  if (nodes.empty() || root == kEmptyChild || (root & kLeafBit) != 0) return 0.0;
  AABB root_box;
  for (int lane = 0; lane < W; ++lane) root_box.extend(child_bounds(nodes[root], lane));
  double total = double(costs.traversal) * root_box.surface_area();
  for (const Node<W>& node : nodes) {
    for (int lane = 0; lane < W; ++lane) {
      const std::uint32_t ref = node.child[lane];
      if (ref == kEmptyChild) continue;
      const double area = child_bounds(node, lane).surface_area();
      total += (ref & kLeafBit) ? area * costs.intersection * leaf_block_count(ref) : area * costs.traversal;
    }
  }
  const double root_area = root_box.surface_area();
  return root_area > 0.0 ? total / root_area : 0.0;
}

}  // namespace

std::size_t WideBvh::memory_bytes() const {
  return nodes4_.size() * sizeof(Node<4>) + nodes8_.size() * sizeof(Node<8>) + blocks_.size() * sizeof(simd::Triangle4);
}

std::vector<BuildStatistic> WideBvh::build_statistics() const {
  std::size_t used_lanes = 0;
  for (const auto& b : blocks_) {
    for (std::uint32_t id : b.prim_id) used_lanes += id != kInvalidPrimId ? 1 : 0;
  }
  return {{"width", double(width_)},
          {"avx512_kernels", isa_ == simd::Isa::avx512 ? 1.0 : 0.0},
          {"nodes", double(nodes4_.size() + nodes8_.size())},
          {"triangle4_blocks", double(blocks_.size())},
          {"block_fill", blocks_.empty() ? 0.0 : double(used_lanes) / (4.0 * blocks_.size())},
          {"depth", double(depth_)},
          {"references", double(references_)},
          {"presplit_triangles", double(split_triangles_)},
          {"presplit_potential", presplit_potential_},
          {"leaf_repeats_dropped", double(dropped_repeats_)},
          {"sah_cost", width_ == 8 ? wide_sah_cost(nodes8_, root_, config_.binary.costs)
                                   : wide_sah_cost(nodes4_, root_, config_.binary.costs)}};
}

}  // namespace rayaccel::wide
