// bvh_wide's per-octant child order (Node::order, the any-hit traversal's visiting order): farthest first along each
// octant's diagonal with unused lanes last, kept through refit, and a saved file whose order is not a permutation of
// the lanes (which would skip children) is refused on load.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "../error_message.h"
#include "rayaccel/bvh/bvh_file.h"
#include "rayaccel/scene/builtin_scenes.h"
#include "rayaccel/wide/wide_bvh.h"
#include "rayaccel/wide/wide_bvh_file.h"

namespace rayaccel::wide {
namespace {

/// The lanes of `word` in visiting order (the first entered first).
template <int W>
std::vector<unsigned> visiting_order(unsigned word) {
  std::vector<unsigned> lanes;
  for (int position = W - 1; position >= 0; --position) lanes.push_back(order_lane(word, position));
  return lanes;
}

TEST(ChildOrder, FarthestFirstAlongEachOctantsDiagonalUnusedLanesLast) {
  Node<8> node{};
  for (int lane = 0; lane < 8; ++lane) set_child_bounds(node, lane, AABB::empty());
  // Five unit boxes along x: lane 0 at x = 2, lane 1 at 0, lane 2 at 4, lane 3 at 1, lane 4 at 3 (lanes 5-7 unused).
  const float x[5] = {2, 0, 4, 1, 3};
  for (int lane = 0; lane < 5; ++lane) set_child_bounds(node, lane, AABB{{x[lane], 0, 0}, {x[lane] + 1, 1, 1}});
  set_child_order(node);
  EXPECT_TRUE(child_order_is_permutation(node));
  for (unsigned octant = 0; octant < 8; ++octant) {
    const std::vector<unsigned> order = visiting_order<8>(node.order[octant]);
    // +x rays meet the box at 4 last; -x rays the one at 0. The y and z signs do not separate these boxes.
    const std::vector<unsigned> along_x = (octant & 1u) ? std::vector<unsigned>{1, 3, 0, 4, 2}
                                                        : std::vector<unsigned>{2, 4, 0, 3, 1};
    EXPECT_EQ(std::vector<unsigned>(order.begin(), order.begin() + 5), along_x) << "octant " << octant;
    EXPECT_EQ(std::vector<unsigned>(order.begin() + 5, order.end()), (std::vector<unsigned>{5, 6, 7}));
  }
  // Position 0 given position 1's lane: that lane twice, position 0's never.
  node.order[3] = (node.order[2] & ~7u) | order_lane(node.order[2], 1);
  EXPECT_FALSE(child_order_is_permutation(node));
}

TEST(ChildOrder, FourWideNodesAndRefitKeepPermutations) {
  const Scene scene = make_builtin_scene("default");
  for (int width : {4, 8}) {
    WideBvhOptions config;
    config.width = width;
    WideBvh bvh(config);
    bvh.build(scene);
    if (bvh.width() != width) continue;  // a CPU without AVX2 builds four-wide nodes only
    ASSERT_TRUE(bvh.validate().empty());
    bvh.refit();
    EXPECT_TRUE(bvh.validate().empty());
    const auto check = [](const auto& nodes) {
      for (const auto& node : nodes) ASSERT_TRUE(child_order_is_permutation(node));
    };
    width == 8 ? check(bvh.nodes8()) : check(bvh.nodes4());
  }
}

TEST(ChildOrder, ALoadedFileWhoseOrderIsNotAPermutationIsRefused) {
  const Scene scene = make_builtin_scene("default");
  WideBvh built;
  built.build(scene);
  const auto dir = std::filesystem::temp_directory_path() / "rayaccel_wide_child_order_test";
  std::filesystem::create_directories(dir);
  const auto good = dir / "good.wbvh", damaged = dir / "damaged.wbvh";
  built.save(good);
  std::ifstream in(good, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // The root node's order for octant 0 set to zero (lane 0 at every position), the checksum made good again, so only
  // the tree check can catch it.
  const std::size_t order_at =
      sizeof(WideBvhFileHeader) + (built.width() == 8 ? offsetof(Node<8>, order) : offsetof(Node<4>, order));
  std::memset(bytes.data() + order_at, 0, built.width() == 8 ? 4 : 2);
  const std::size_t body = bytes.size() - sizeof(std::uint64_t);
  const std::uint64_t sum = bvh_checksum(std::as_bytes(std::span(bytes.data(), body)));
  std::memcpy(bytes.data() + body, &sum, sizeof sum);
  std::ofstream(damaged, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  WideBvh loaded;
  const std::string message = testing::error_message([&] { loaded.load(damaged, scene); });
  EXPECT_TRUE(testing::contains(message, damaged.string())) << message;
  EXPECT_TRUE(testing::contains(message, "child order is not a permutation")) << message;
  loaded.load(good, scene);  // the undamaged file loads
  EXPECT_TRUE(loaded.validate().empty());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rayaccel::wide
