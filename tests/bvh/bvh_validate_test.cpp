// validate() must catch deliberately corrupted trees: shrunken volumes, lost or duplicated primitives, child indices
// out of range, oversized leaves, nodes reached twice. Also checks the reported build statistics.
#include <gtest/gtest.h>

#include "bvh_test_scenes.h"
#include "rayaccel/bvh/bvh.h"

namespace rayaccel {

/// Test-only access to a Bvh's arrays, for corrupting a built tree.
struct BvhTestAccess {
  template <class BV>
  static std::vector<BvhNode<BV>>& nodes(Bvh<BV>& bvh) { return bvh.nodes_; }
  template <class BV>
  static std::vector<std::uint32_t>& prim_ids(Bvh<BV>& bvh) { return bvh.prim_ids_; }
};

namespace {

bool mentions(const std::vector<std::string>& problems, const std::string& text) {
  for (const auto& p : problems) {
    if (p.find(text) != std::string::npos) return true;
  }
  return false;
}

class BvhValidate : public ::testing::Test {
 protected:
  void SetUp() override {
    bvh_.build(scene_);
    ASSERT_TRUE(bvh_.validate().empty());
    for (std::uint32_t i = 0; i < bvh_.nodes().size(); ++i) {
      if (bvh_.nodes()[i].is_leaf() && leaf_ == 0) leaf_ = i;
      if (!bvh_.nodes()[i].is_leaf() && i > 0 && interior_ == 0) interior_ = i;
    }
    ASSERT_GT(leaf_, 0u);
    ASSERT_GT(interior_, 0u);
  }
  Scene scene_ = bvh_test::random_soup(500, 31);
  Bvh<AabbVolume> bvh_;
  std::uint32_t leaf_ = 0, interior_ = 0;
};

TEST_F(BvhValidate, CatchesShrunkenLeafVolume) {
  auto& box = BvhTestAccess::nodes(bvh_)[leaf_].volume.box;
  box.hi = box.lo + (box.hi - box.lo) * 0.5f;
  EXPECT_TRUE(mentions(bvh_.validate(), "is outside the volume"));
}

TEST_F(BvhValidate, CatchesParentNotEnclosingChild) {
  auto& box = BvhTestAccess::nodes(bvh_)[0].volume.box;
  box.lo.x += 0.1f;
  EXPECT_TRUE(mentions(bvh_.validate(), "node 0: primitive"));
}

TEST_F(BvhValidate, CatchesDuplicatedAndLostPrimitive) {
  auto& ids = BvhTestAccess::prim_ids(bvh_);
  const std::uint32_t lost = ids[0];
  ids[0] = ids[1];
  const auto problems = bvh_.validate();
  EXPECT_TRUE(mentions(problems, "primitive " + std::to_string(lost) + " is referenced 0 times"));
  EXPECT_TRUE(mentions(problems, "primitive " + std::to_string(ids[1]) + " is referenced 2 times"));
}

TEST_F(BvhValidate, CatchesInvalidPrimitiveId) {
  BvhTestAccess::prim_ids(bvh_)[3] = 100000;
  EXPECT_TRUE(mentions(bvh_.validate(), "which is out of range"));
}

TEST_F(BvhValidate, CatchesChildIndexOutOfRange) {
  BvhTestAccess::nodes(bvh_)[interior_].index = static_cast<std::uint32_t>(bvh_.nodes().size()) + 7;
  EXPECT_TRUE(mentions(bvh_.validate(), "out of range"));
}

TEST_F(BvhValidate, CatchesNodeReachedTwice) {
  auto& nodes = BvhTestAccess::nodes(bvh_);
  nodes[0].index = 1 + 1;  // second child of the root now points into the first child's subtree
  const auto problems = bvh_.validate();
  EXPECT_TRUE(mentions(problems, "reached more than once") || mentions(problems, "unreachable"));
}

TEST_F(BvhValidate, CatchesOversizedLeaf) {
  BvhTestAccess::nodes(bvh_)[leaf_].count = bvh_.options().max_leaf_size + 1;
  EXPECT_TRUE(mentions(bvh_.validate(), "more than " + std::to_string(bvh_.options().max_leaf_size)));
}

TEST(BvhStatistics, ReportsCountsCostAndTightness) {
  const Scene scene = bvh_test::random_soup(1000, 32);
  Bvh<AabbVolume> bvh;
  bvh.build(scene);
  std::map<std::string, double> stats;
  for (const auto& s : bvh.build_statistics()) stats[s.name] = s.value;
  EXPECT_EQ(stats.at("node_count"), static_cast<double>(bvh.nodes().size()));
  EXPECT_EQ(stats.at("node_count"), 2 * stats.at("leaf_count") - 1);
  EXPECT_EQ(stats.at("depth"), bvh.depth());
  EXPECT_EQ(stats.at("references_per_primitive"), 1.0);
  EXPECT_EQ(stats.at("volume_tightness"), 1.0);  // an AABB is its own box
  EXPECT_EQ(stats.at("sah_traversal_cost"), 1.0);
  // A tree costs at least one primitive test per ray reaching the root and at most testing everything.
  EXPECT_GT(stats.at("sah_cost"), 1.0);
  EXPECT_LT(stats.at("sah_cost"), 1000.0);
}

TEST(BvhStatistics, EmptySceneBuildsAnEmptyTree) {
  const Scene scene = Scene::from_mesh({}, "empty");
  Bvh<AabbVolume> bvh;
  bvh.build(scene);
  EXPECT_TRUE(bvh.nodes().empty());
  EXPECT_TRUE(bvh.validate().empty());
  EXPECT_EQ(bvh.depth(), 0);
}

}  // namespace
}  // namespace rayaccel
