// The binned SAH builder's shortcuts keep its tree: centroid bounds carried from a split to its children, and large
// nodes binned by several threads, give the tree of the plain recursion (a fresh centroid pass per node, one thread).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <random>
#include <vector>

#include "rayaccel/bvh/binned_sah_builder.h"
#include "rayaccel/bvh/top_down_builder.h"

namespace rayaccel {
namespace {

/// Boxes of random size at random places, with clusters so that the splits are not all alike.
PrimRefs random_boxes(std::uint32_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  PrimRefs refs;
  for (std::uint32_t i = 0; i < n; ++i) {
    const float cluster = (i % 7 == 0) ? 0.01f : 1.0f;
    const Vec3 lo{unit(rng) * cluster, unit(rng), unit(rng) * 100.0f};
    const Vec3 size{unit(rng) * 0.01f, unit(rng) * 0.02f, unit(rng) * 0.5f};
    refs.push_back({AABB(lo, lo + size), i});
  }
  return refs;
}

/// The tree as its leaves in depth-first order (left child first), each leaf's references in their order: the same
/// list for two trees of the same shape, however their nodes are numbered.
std::vector<std::vector<std::uint32_t>> leaves_in_order(const BuildTree& tree) {
  std::vector<std::vector<std::uint32_t>> leaves;
  std::vector<std::uint32_t> pending{0};
  while (!pending.empty()) {
    const BuildNode n = tree.nodes.at(pending.back());
    pending.pop_back();
    if (n.is_leaf()) {
      leaves.emplace_back();
      for (std::uint32_t k = n.first; k < n.first + n.count; ++k) leaves.back().push_back(tree.refs.at(k).prim_id);
    } else {
      pending.push_back(n.first + 1);
      pending.push_back(n.first);
    }
  }
  return leaves;
}

/// The binned SAH recursion through the public find and partition steps, without the builder's shortcuts.
BuildTree plain_binned_sah(PrimRefs refs, const BinnedSahOptions& config) {
  const int block_shift = __builtin_ctz(config.block_size);
  const std::size_t always_leaf = std::min<std::size_t>(config.max_leaf_size, config.block_size);
  return build_top_down(std::move(refs), {config.max_leaf_size, config.parallel_threshold},
                        [&](std::uint32_t, std::span<PrimRef> node_refs) -> std::size_t {
                          if (node_refs.size() <= always_leaf) return 0;
                          const BinnedSplit split = find_binned_split(node_refs, config.bin_count, block_shift);
                          if (split.axis < 0) return 0;
                          const float area = merge(split.left, split.right).surface_area();
                          if (sah_prefers_leaf(node_refs.size(), area, split.cost, config.max_leaf_size, config.costs,
                                               block_shift)) {
                            return 0;
                          }
                          return partition_binned(node_refs, split, config.bin_count);
                        });
}

TEST(BvhBinnedSah, ShortcutsKeepThePlainRecursionsTree) {
  // Over 2^15 references, so the top nodes take the parallel binning path; the wide BVH's options (blocks of 4).
  const BinnedSahOptions config{.max_leaf_size = 8, .costs = {}, .bin_count = 16, .block_size = 4};
  for (const std::uint32_t seed : {1u, 2u}) {
    const PrimRefs refs = random_boxes(100000, seed);
    std::vector<std::vector<std::uint32_t>> plain;
    {
      const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
      plain = leaves_in_order(plain_binned_sah(refs, config));
    }
    EXPECT_GT(plain.size(), 10000u);
    // With the threads TBB has (two or more here) and with one.
    EXPECT_EQ(leaves_in_order(build_binned_sah(refs, config)), plain) << "seed " << seed;
    const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    EXPECT_EQ(leaves_in_order(build_binned_sah(refs, config)), plain) << "seed " << seed << ", one thread";
  }
}

}  // namespace
}  // namespace rayaccel
