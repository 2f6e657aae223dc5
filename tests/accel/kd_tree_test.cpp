// kd-tree tests: every variant against brute force on adversarial scenes, node packing, polygon clipping (perfect
// splits), options and build statistics.
#include "rayaccel/accel/kd_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "rayaccel/core/error.h"
#include "rayaccel/geometry/clip_polygon.h"
#include "split_plane_oracle.h"

namespace rayaccel {
namespace {

std::map<std::string, double> statistics(const Accelerator& accel) {
  std::map<std::string, double> out;
  for (const auto& s : accel.build_statistics()) out[s.name] = s.value;
  return out;
}

TEST(KdTree, MedianMatchesBruteForce) { spatial_test::run_oracle_cases("kdtree:builder=median"); }
TEST(KdTree, SahMatchesBruteForce) { spatial_test::run_oracle_cases("kdtree:builder=sah"); }
TEST(KdTree, SahWithMailboxMatchesBruteForce) { spatial_test::run_oracle_cases("kdtree:builder=sah,mailbox=true"); }
TEST(KdTree, DeepMedianTreeWithOneReferencePerLeafMatches) {
  spatial_test::run_oracle_cases("kdtree:builder=median,leaf_size=1,max_depth=40");
}
TEST(KdTree, CheapTraversalSahMatches) {
  spatial_test::run_oracle_cases("kdtree:builder=sah,traversal_cost=1,intersection_cost=80");
}

TEST(KdTree, NodePackingRoundTrips) {
  const KdNode interior = KdNode::interior(2, -3.5f, 123456);
  EXPECT_FALSE(interior.is_leaf());
  EXPECT_EQ(interior.axis(), 2);
  EXPECT_EQ(interior.above_child(), 123456u);
  EXPECT_EQ(interior.split, -3.5f);
  const KdNode leaf = KdNode::leaf(77, KdNode::kMaxField);
  EXPECT_TRUE(leaf.is_leaf());
  EXPECT_EQ(leaf.prim_count(), KdNode::kMaxField);
  EXPECT_EQ(leaf.prim_offset, 77u);
}

TEST(ClipPolygon, TriangleClippedToBoxGivesTightBounds) {
  // A large right triangle in z = 0.5 clipped to the unit box: the part inside is the unit square's lower triangle.
  const AABB box{{0, 0, 0}, {1, 1, 1}};
  const AABB b = clip_triangle_to_box({-1, -1, 0.5f}, {3, -1, 0.5f}, {-1, 3, 0.5f}, box);
  EXPECT_EQ(b, AABB({0, 0, 0.5f}, {1, 1, 0.5f}));
  // The thin diagonal sliver from (0,0) to (4,4) crosses the box [2,3]x[0,1] nowhere (its bounds overlap it).
  EXPECT_TRUE(clip_triangle_to_box({0, 0, 0}, {4, 4.01f, 0}, {4, 3.99f, 0}, AABB({2, 0, -1}, {3, 1, 1})).is_empty());
  // A triangle that only touches the box face is kept, flat.
  const AABB touching = clip_triangle_to_box({1, 0, 0}, {2, 0, 0}, {1, 1, 0}, AABB({0, 0, -1}, {1, 1, 1}));
  EXPECT_FALSE(touching.is_empty());
  EXPECT_EQ(touching.lo.x, 1.0f);
}

TEST(ClipPolygon, HalfspaceClipKeepsAreaOnOneSide) {
  const Vec3 square[4] = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
  Vec3 out[5];
  const int n = clip_polygon_to_halfspace(square, 4, normalize(Vec3{1, 1, 0}), std::sqrt(0.5), out);
  EXPECT_EQ(n, 3);  // x + y <= 1 keeps the corner triangle of area 1/2
  EXPECT_NEAR(polygon_area(out, n), 0.5, 1e-6);
  EXPECT_EQ(clip_polygon_to_halfspace(square, 4, {0, 0, 1}, -1.0, out), 0);
}

TEST(KdTree, SahCutsOffEmptySpaceAndReportsStatistics) {
  // A soup of small triangles in [-1, 1]^3 and one more triangle far off at (8, 8, 8): most of the scene box is empty,
  // and the SAH (with its empty-space bonus) cuts that space off into empty leaves.
  TriangleMesh mesh = testing::random_soup(2000, 21, 0.02f);
  const auto far_vertex = static_cast<std::uint32_t>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), {{8.0f, 8.0f, 8.0f}, {8.1f, 8.0f, 8.0f}, {8.0f, 8.1f, 8.0f}});
  mesh.triangles.push_back({far_vertex, far_vertex + 1, far_vertex + 2});
  const Scene scene = Scene::from_mesh(std::move(mesh), "soup and a far triangle");
  auto sah = make_accelerator("kdtree:builder=sah");
  auto median = make_accelerator("kdtree:builder=median");
  sah->build(scene);
  median->build(scene);
  const auto s = statistics(*sah), m = statistics(*median);
  EXPECT_GT(s.at("empty_leaves"), 0.0);
  EXPECT_GE(s.at("references_per_primitive"), 1.0);
  EXPECT_LE(s.at("max_depth"), double(kd_tree_max_depth({}, 2001)));
  EXPECT_LT(s.at("sah_cost"), m.at("sah_cost"));
  EXPECT_EQ(s.at("nodes"), double(dynamic_cast<const KdTree&>(*sah).data().nodes.size()));
  // Nodes, the reference array, and the Triangle4 copy of the leaves (one block start per node, plus one).
  EXPECT_EQ(sah->memory_bytes(), std::size_t(s.at("nodes")) * 8 +
                                     dynamic_cast<const KdTree&>(*sah).data().prim_indices.size() * 4 +
                                     (std::size_t(s.at("nodes")) + 1) * 4 +
                                     std::size_t(s.at("triangle4_blocks")) * sizeof(simd::Triangle4));
  EXPECT_GT(s.at("block_fill"), 0.5);
}

TEST(KdTree, MailboxSavesTestsOnStraddlingTriangles) {
  const Scene scene = spatial_test::random_soup(500, 31, 0.5f);
  auto plain = make_accelerator("kdtree:builder=median,leaf_size=1");
  auto boxed = make_accelerator("kdtree:builder=median,leaf_size=1,mailbox=true");
  plain->build(scene);
  boxed->build(scene);
  TraversalStats a, b;
  for (const Ray& r : spatial_test::random_rays(200, 32)) {
    plain->intersect(r, a);
    boxed->intersect(r, b);
  }
  EXPECT_EQ(a.nodes_visited, b.nodes_visited);
  EXPECT_LT(b.primitives_tested, a.primitives_tested);
}

TEST(KdTree, DepthLimitIsHonoured) {
  const Scene scene = spatial_test::random_soup(1000, 41);
  auto accel = make_accelerator("kdtree:builder=median,leaf_size=1,max_depth=5");
  accel->build(scene);
  EXPECT_LE(statistics(*accel).at("max_depth"), 5.0);
  EXPECT_TRUE(accel->validate().empty());
}

TEST(KdTree, ValidateReportsCorruptedTrees) {
  const Scene scene = spatial_test::random_soup(500, 51);
  KdTree tree(KdTreeOptions{});
  tree.build(scene);
  ASSERT_TRUE(tree.validate().empty());
  // The tree object is not const, so writing through the const view is well defined; each edit breaks one invariant.
  auto& data = const_cast<KdTreeData&>(tree.data());
  const KdTreeData good = data;
  auto first_leaf = std::find_if(data.nodes.begin(), data.nodes.end(),
                                 [](const KdNode& n) { return n.is_leaf() && n.prim_count() > 0; });
  ASSERT_NE(first_leaf, data.nodes.end());
  auto interior = std::find_if(data.nodes.begin(), data.nodes.end(), [](const KdNode& n) { return !n.is_leaf(); });
  ASSERT_NE(interior, data.nodes.end());

  data.prim_indices[first_leaf->prim_offset] = (data.prim_indices[first_leaf->prim_offset] + 250) % 500;
  EXPECT_FALSE(tree.validate().empty()) << "a reference moved to a far leaf";
  data = good;
  interior->split = 1e6f;
  EXPECT_FALSE(tree.validate().empty()) << "a split outside its cell";
  data = good;
  first_leaf->bits = (std::uint32_t(data.prim_indices.size()) << 2) | KdNode::kLeafTag;
  EXPECT_FALSE(tree.validate().empty()) << "a leaf range past the index array";
  data = good;
  interior->bits = (std::uint32_t(data.nodes.size() + 5) << 2) | std::uint32_t(interior->axis());
  EXPECT_FALSE(tree.validate().empty()) << "a child index out of range";
  data = good;
  data.prim_indices.assign(data.prim_indices.size(), data.prim_indices.front());
  EXPECT_FALSE(tree.validate().empty()) << "primitives in no leaf";
  data = good;
  EXPECT_TRUE(tree.validate().empty());
}

TEST(KdTree, RejectsBadOptions) {
  EXPECT_THROW(make_accelerator("kdtree:builder=binned"), Error);
  EXPECT_THROW(make_accelerator("kdtree:max_depth=-1"), Error);
  EXPECT_THROW(make_accelerator("kdtree:max_depth=1000"), Error);
  EXPECT_THROW(make_accelerator("kdtree:leaf_size=0"), Error);
  EXPECT_THROW(make_accelerator("kdtree:empty_bonus=1"), Error);
  EXPECT_THROW(make_accelerator("kdtree:traversal_cost=0"), Error);
  EXPECT_THROW(make_accelerator("kdtree:leafsize=2"), Error);
}

TEST(KdTree, NanAndZeroDirectionRaysMiss) {
  const Scene scene = spatial_test::closed_sphere(8, 8);
  auto accel = make_accelerator("kdtree");
  accel->build(scene);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(accel->intersect(Ray{{0, 0, -3}, 0, {0, 0, 0}, 10}).found());
  EXPECT_FALSE(accel->occluded(Ray{{0, 0, -3}, 0, {nan, 0, 1}, 10}));
  EXPECT_TRUE(accel->intersect(Ray{{0, 0, -3}, 0, {0, 0, 1}, 10}).found());
}

}  // namespace
}  // namespace rayaccel
