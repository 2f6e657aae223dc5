// The SBVH builder's block costing (SbvhOptions::block_size, as bvh_wide's spatial=F uses it): leaves priced per
// started block hold fuller blocks than leaves priced per reference, and a block size that is not a power of two in
// 1..64 is refused by name. Its parallel build: subtrees built on other threads and spliced in make a well-formed
// tree, the same on one thread as on several.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <string>
#include <vector>

#include "rayaccel/bvh/sbvh_builder.h"
#include "rayaccel/core/error.h"
#include "rayaccel/scene/builtin_scenes.h"

namespace rayaccel {
namespace {

/// References in leaves, over leaves.
double mean_leaf_size(const BuildTree& tree) {
  std::size_t leaves = 0, refs = 0;
  for (const BuildNode& node : tree.nodes) {
    if (!node.is_leaf()) continue;
    ++leaves;
    refs += node.count;
  }
  return leaves ? double(refs) / double(leaves) : 0.0;
}

TEST(SbvhBlocks, BlockCostingMakesFullerLeaves) {
  const Scene scene = make_builtin_scene("default");
  SbvhOptions single{.max_leaf_size = 8, .costs = {}, .bin_count = 16, .max_growth = 1.2f};
  SbvhOptions blocks = single;
  blocks.block_size = 4;
  const BuildTree by_reference = build_sbvh(scene, single);
  const BuildTree by_block = build_sbvh(scene, blocks);
  ASSERT_FALSE(by_block.nodes.empty());
  // Four references cost what one does, so splitting a leaf of four or fewer never pays.
  EXPECT_GT(mean_leaf_size(by_block), mean_leaf_size(by_reference) + 1.0);
  EXPECT_LE(by_block.refs.size(), static_cast<std::size_t>(1.2 * double(scene.primitive_count())) + 1);
}

TEST(SbvhBlocks, ABlockSizeOutsidePowersOfTwoIsRefused) {
  const Scene scene = make_builtin_scene("default");
  for (std::uint32_t size : {0u, 3u, 128u}) {
    try {
      SbvhOptions options;
      options.block_size = size;
      build_sbvh(scene, options);
      FAIL() << "block size " << size << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("block size " + std::to_string(size)), std::string::npos) << e.what();
    }
  }
}

/// Walks the tree depth first: every node is reached once, the leaves' ranges follow each other from the first
/// reference to the last, and every primitive is referenced. Returns the number of references split (duplicates).
std::size_t expect_well_formed(const BuildTree& tree, std::uint32_t primitives) {
  std::vector<char> reached(tree.nodes.size(), 0), referenced(primitives, 0);
  std::vector<std::uint32_t> stack{0};
  std::uint32_t next_ref = 0;
  while (!stack.empty()) {
    const std::uint32_t index = stack.back();
    stack.pop_back();
    EXPECT_LT(index, tree.nodes.size());
    if (index >= tree.nodes.size()) return 0;
    EXPECT_FALSE(reached[index]) << "node " << index << " reached twice";
    reached[index] = 1;
    const BuildNode& node = tree.nodes[index];
    if (!node.is_leaf()) {
      stack.push_back(node.first + 1);  // the left child is taken first
      stack.push_back(node.first);
      continue;
    }
    EXPECT_EQ(node.first, next_ref) << "leaf " << index << " does not follow the previous leaf";
    next_ref = node.first + node.count;
    for (std::uint32_t r = node.first; r < next_ref && r < tree.refs.size(); ++r) referenced[tree.refs[r].prim_id] = 1;
  }
  EXPECT_EQ(next_ref, tree.refs.size());
  EXPECT_EQ(std::count(reached.begin(), reached.end(), 1), static_cast<std::ptrdiff_t>(tree.nodes.size()));
  EXPECT_EQ(std::count(referenced.begin(), referenced.end(), 1), static_cast<std::ptrdiff_t>(primitives));
  return tree.refs.size() - primitives;
}

TEST(SbvhParallel, SplicedSubtreesMakeTheOneThreadTree) {
  const Scene scene = make_builtin_scene("default");
  ASSERT_GT(scene.primitive_count(), 4 * 2048u);  // two levels or more of subtrees built in parallel and spliced
  const SbvhOptions options{.max_leaf_size = 8, .costs = {}, .bin_count = 16, .max_growth = 1.3f, .block_size = 4};
  BuildTree one, many;
  tbb::task_arena(1).execute([&] { one = build_sbvh(scene, options); });
  tbb::task_arena(4).execute([&] { many = build_sbvh(scene, options); });
  EXPECT_GT(expect_well_formed(many, scene.primitive_count()), 0u);  // spatial splits were made
  expect_well_formed(one, scene.primitive_count());
  ASSERT_EQ(one.nodes.size(), many.nodes.size());
  ASSERT_EQ(one.refs.size(), many.refs.size());
  for (std::size_t i = 0; i < one.nodes.size(); ++i) {
    ASSERT_EQ(one.nodes[i].first, many.nodes[i].first) << "node " << i;
    ASSERT_EQ(one.nodes[i].count, many.nodes[i].count) << "node " << i;
  }
  for (std::size_t i = 0; i < one.refs.size(); ++i) {
    ASSERT_EQ(one.refs[i].prim_id, many.refs[i].prim_id) << "reference " << i;
    ASSERT_EQ(one.refs[i].bounds.lo, many.refs[i].bounds.lo) << "reference " << i;
    ASSERT_EQ(one.refs[i].bounds.hi, many.refs[i].bounds.hi) << "reference " << i;
  }
}

}  // namespace
}  // namespace rayaccel
