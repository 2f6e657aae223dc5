// The SBVH builder's block costing (SbvhOptions::block_size, as bvh_wide's spatial=F uses it): leaves priced per
// started block hold fuller blocks than leaves priced per reference, and a block size that is not a power of two in
// 1..64 is refused by name.
#include <gtest/gtest.h>

#include <string>

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

}  // namespace
}  // namespace rayaccel
