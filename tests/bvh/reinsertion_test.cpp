// Insertion-based optimisation (bvh/reinsertion.h): the cost it reports is the rewritten tree's own, it never rises,
// it falls clearly on a poor tree, and the rewritten tree is a valid builder tree over the same leaves.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <vector>

#include "rayaccel/bvh/binned_sah_builder.h"
#include "rayaccel/bvh/reinsertion.h"
#include "rayaccel/scene/builtin_scenes.h"

namespace rayaccel {
namespace {

/// Area-weighted SAH cost of a builder tree, computed from scratch (traversal 1 per interior node, 1 per started
/// block of `block` references per leaf).
double tree_cost(const BuildTree& tree, std::uint32_t block) {
  std::vector<AABB> box(tree.nodes.size());
  double total = 0.0;
  for (std::size_t i = tree.nodes.size(); i-- > 0;) {
    const BuildNode& n = tree.nodes[i];
    if (n.is_leaf()) {
      for (std::uint32_t r = n.first; r < n.first + n.count; ++r) box[i].extend(tree.refs[r].bounds);
      total += double(box[i].surface_area()) * double((n.count + block - 1) / block);
    } else {
      box[i] = merge(box[n.first], box[n.first + 1]);
      total += box[i].surface_area();
    }
  }
  return total;
}

/// Every reference in exactly one leaf, children after their parent, every node but the root reached once.
void expect_valid_tree(const BuildTree& tree) {
  std::vector<int> ref_seen(tree.refs.size(), 0), node_seen(tree.nodes.size(), 0);
  node_seen[0] = 1;
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
    const BuildNode& n = tree.nodes[i];
    if (n.is_leaf()) {
      ASSERT_LE(std::size_t{n.first} + n.count, tree.refs.size());
      for (std::uint32_t r = n.first; r < n.first + n.count; ++r) ++ref_seen[r];
    } else {
      ASSERT_GT(n.first, i);
      ASSERT_LT(std::size_t{n.first} + 1, tree.nodes.size());
      ++node_seen[n.first];
      ++node_seen[n.first + 1];
    }
  }
  for (int seen : ref_seen) ASSERT_EQ(seen, 1);
  for (int seen : node_seen) ASSERT_EQ(seen, 1);
}

TEST(Reinsertion, NeverRaisesTheCostAndReportsTheTreesOwn) {
  for (const char* name : {"default", "soup", "slivers"}) {
    const Scene scene = make_builtin_scene(name);
    const BinnedSahOptions binned{.max_leaf_size = 8, .costs = {}, .bin_count = 16, .block_size = 4};
    BuildTree tree = build_binned_sah(scene.build_references(), binned);
    const double before = tree_cost(tree, 4);
    const ReinsertionResult result = reinsert_nodes(tree, {.costs = {}, .block_size = 4, .max_batches = 8});
    expect_valid_tree(tree);
    EXPECT_NEAR(result.cost_before, before, 1e-6 * before) << name;
    EXPECT_NEAR(result.cost_after, tree_cost(tree, 4), 1e-6 * before) << name;
    EXPECT_LE(result.cost_after, before * (1.0 + 1e-9)) << name;
    EXPECT_GE(result.batches, 1u);
  }
}

/// A tree that ignores space: the references shuffled, then halved by position down to leaves of one.
BuildTree random_tree(PrimRefs refs, unsigned seed) {
  std::mt19937 rng(seed);
  std::shuffle(refs.begin(), refs.end(), rng);
  BuildTree tree;
  tree.refs = std::move(refs);
  tree.nodes.resize(1);
  std::vector<std::array<std::uint32_t, 3>> pending{{0, 0, static_cast<std::uint32_t>(tree.refs.size())}};
  while (!pending.empty()) {
    const auto [node, first, count] = pending.back();
    pending.pop_back();
    if (count <= 1) {
      tree.nodes[node] = {first, count};
      continue;
    }
    const auto child = static_cast<std::uint32_t>(tree.nodes.size());
    tree.nodes.resize(tree.nodes.size() + 2);
    tree.nodes[node] = {child, 0};
    pending.push_back({child, first, count / 2});
    pending.push_back({child + 1, first + count / 2, count - count / 2});
  }
  return tree;
}

TEST(Reinsertion, MendsAPoorTree) {
  // Grouped by chance, not by place: moving subtrees to where they fit must win back much of the cost.
  const Scene scene = make_builtin_scene("default");
  BuildTree tree = random_tree(scene.build_references(), 3);
  const double before = tree_cost(tree, 1);
  const ReinsertionResult result = reinsert_nodes(tree, {.costs = {}, .max_batches = 64, .min_gain = 0.0f});
  expect_valid_tree(tree);
  EXPECT_LT(tree_cost(tree, 1), 0.5 * before);
  EXPECT_GT(result.moves, 100u);
}

}  // namespace
}  // namespace rayaccel
