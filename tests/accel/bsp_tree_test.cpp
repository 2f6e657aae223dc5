// BSP tree tests: against brute force on adversarial scenes, cell polytopes, options, and the figure that shows
// where arbitrary planes beat the kd-tree (a rotated stack of thin triangles).
#include "rayaccel/accel/bsp_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>

#include "rayaccel/core/error.h"
#include "rayaccel/geometry/clip_polygon.h"
#include "split_plane_oracle.h"

namespace rayaccel {
namespace {

TEST(BspTree, MatchesBruteForce) { spatial_test::run_oracle_cases("bsp"); }
TEST(BspTree, BinnedCandidatesOnlyMatchBruteForce) { spatial_test::run_oracle_cases("bsp:exact_threshold=0"); }
TEST(BspTree, FixedDirectionsOnlyMatchBruteForce) {
  spatial_test::run_oracle_cases("bsp:own_planes=false,leaf_size=2");
}

TEST(BspPolytope, BoxAreaAndSplitAreas) {
  const Polytope box = Polytope::from_box(AABB({0, 0, 0}, {2, 2, 2}));
  EXPECT_NEAR(box.surface_area(), 24.0, 1e-9);
  // Cutting a 2-cube through the diagonal plane x + y = 2 gives two triangular prisms, each with two triangles of
  // area 2, two 2x2 squares and the 2 x 2*sqrt(2) cut.
  const Vec3 n = normalize(Vec3{1, 1, 0});
  const double d = std::sqrt(2.0);
  double below = 0.0, above = 0.0;
  box.split_areas(n, d, below, above);
  const double expected = 12.0 + 4.0 * std::sqrt(2.0);
  EXPECT_NEAR(below, expected, 1e-4);
  EXPECT_NEAR(above, expected, 1e-4);
  const Polytope half = box.clip(n, d, true);
  EXPECT_NEAR(half.surface_area(), below, 1e-4);
  int proper_faces = 0;  // faces the plane only grazes along an edge remain as slivers (the normal is a float)
  for (const auto& f : half.faces()) proper_faces += polygon_area(f.vertices.data(), int(f.vertices.size())) > 1e-6;
  EXPECT_EQ(proper_faces, 5);
  // A plane beyond the box leaves everything on one side and nothing on the other.
  box.split_areas({1, 0, 0}, 5.0, below, above);
  EXPECT_NEAR(below, 24.0, 1e-9);
  EXPECT_EQ(above, 0.0);
  EXPECT_TRUE(box.clip({1, 0, 0}, 5.0, false).is_empty());
}

TEST(BspTree, ValidateReportsCorruptedTrees) {
  const Scene scene = spatial_test::random_soup(300, 52);
  BspTree tree;
  tree.build(scene);
  ASSERT_TRUE(tree.validate().empty());
  // The tree object is not const, so writing through the const view is well defined; each edit breaks one invariant.
  auto& data = const_cast<BspTreeData&>(tree.data());
  const BspTreeData good = data;
  auto interior = std::find_if(data.nodes.begin(), data.nodes.end(), [](const BspNode& n) { return !n.is_leaf(); });
  ASSERT_NE(interior, data.nodes.end());
  interior->offset += 10.0f;  // every reference below now lies outside its cell
  EXPECT_FALSE(tree.validate().empty()) << "a plane moved away";
  data = good;
  interior->normal = interior->normal * 2.0f;
  EXPECT_FALSE(tree.validate().empty()) << "a normal that is not unit length";
  data = good;
  data.max_depth = 1;
  EXPECT_FALSE(tree.validate().empty()) << "a tree deeper than its limit";
  data = good;
  data.prim_indices.assign(data.prim_indices.size(), data.prim_indices.front());
  EXPECT_FALSE(tree.validate().empty()) << "primitives in no leaf";
  data = good;
  EXPECT_TRUE(tree.validate().empty());
}

TEST(BspTree, RejectsBadOptions) {
  EXPECT_THROW(make_accelerator("bsp:max_depth=99"), Error);
  EXPECT_THROW(make_accelerator("bsp:leaf_size=0"), Error);
  EXPECT_THROW(make_accelerator("bsp:exact_threshold=-1"), Error);
  EXPECT_THROW(make_accelerator("bsp:intersection_cost=-3"), Error);
  EXPECT_THROW(make_accelerator("bsp:planes=13"), Error);
}

/// A stack of thin, long triangles in parallel planes, rotated so that no axis is aligned with them: every
/// triangle's bounding box overlaps most others, which no axis-aligned plane can separate.
Scene rotated_slivers(int layers, int per_layer) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> offset(-0.9f, 0.9f);
  const float c1 = std::cos(0.6f), s1 = std::sin(0.6f), c2 = std::cos(0.8f), s2 = std::sin(0.8f);
  auto rotate = [&](Vec3 p) {
    p = {p.x, c1 * p.y - s1 * p.z, s1 * p.y + c1 * p.z};
    return Vec3{c2 * p.x + s2 * p.z, p.y, -s2 * p.x + c2 * p.z};
  };
  TriangleMesh mesh;
  for (int k = 0; k < layers; ++k) {
    const float z = -1.0f + 2.0f * float(k) / float(layers - 1);
    for (int j = 0; j < per_layer; ++j) {
      const float y = offset(rng);
      const auto base = std::uint32_t(mesh.vertices.size());
      mesh.vertices.push_back(rotate({-1.0f, y, z}));
      mesh.vertices.push_back(rotate({1.0f, y + 0.01f, z}));
      mesh.vertices.push_back(rotate({1.0f, y - 0.01f, z}));
      mesh.triangles.push_back({base, base + 1, base + 2});
    }
  }
  return Scene::from_mesh(std::move(mesh), "rotated_slivers");
}

TEST(BspTree, BeatsKdTreeOnRotatedSlivers) {
  const Scene scene = rotated_slivers(60, 4);
  const std::vector<Ray> rays = spatial_test::random_rays(2000, 77);
  std::map<std::string, TraversalStats> per_spec;
  std::printf("rotated slivers (%u triangles), %zu random rays, per ray:\n", scene.primitive_count(), rays.size());
  for (const std::string spec : {"kdtree:builder=sah", "kdtree:builder=median", "bsp"}) {
    auto accel = make_accelerator(spec);
    accel->build(scene);
    ASSERT_TRUE(accel->validate().empty()) << spec;
    TraversalStats stats;
    for (const Ray& r : rays) accel->intersect(r, stats);
    per_spec[spec] = stats;
    std::printf("  %-22s nodes visited %7.2f  primitives tested %7.2f  memory %zu B\n", spec.c_str(),
                double(stats.nodes_visited) / double(rays.size()), double(stats.primitives_tested) / double(rays.size()),
                accel->memory_bytes());
  }
  spatial_test::expect_matches_brute_force("bsp", scene, rays, "rotated slivers");
  EXPECT_LT(per_spec["bsp"].primitives_tested * 2, per_spec["kdtree:builder=sah"].primitives_tested);
}

}  // namespace
}  // namespace rayaccel
