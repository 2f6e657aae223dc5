// Two-level grid against brute force: soups, a dense cluster in a large sparse box (teapot in a stadium), quad
// lattices with rays along lattice planes, +-0 directions; options and validate() (empty, one-triangle and sphere
// scenes: the conformance suite, for every structure).
#include "rayaccel/accel/two_level_grid.h"

#include <gtest/gtest.h>

#include "rayaccel/core/error.h"
#include "spatial_oracle.h"

namespace rayaccel {
namespace {

using testing::expect_matches_brute_force;
using testing::expect_valid;

double statistic(const Accelerator& a, const std::string& name) {
  for (const auto& s : a.build_statistics()) {
    if (s.name == name) return s.value;
  }
  return -1.0;
}

/// A dense soup of small triangles in [-0.01, 0.01]^3 inside a box of quads 100 units across.
TriangleMesh teapot_in_stadium() {
  TriangleMesh m = testing::random_soup(4000, 5, 0.0005f);
  for (auto& v : m.vertices) v = v * 0.01f;
  const TriangleMesh walls = testing::quad_lattice(1);
  const auto base = std::uint32_t(m.vertices.size());
  for (const auto& v : walls.vertices) m.vertices.push_back((v - Vec3{0.5f}) * 100.0f);
  for (const auto& t : walls.triangles) m.triangles.push_back({base + t[0], base + t[1], base + t[2]});
  return m;
}

TEST(TwoLevelGrid, MatchesBruteForceOnSoupForEveryVariant) {
  const Scene scene = Scene::from_mesh(testing::random_soup(3000, 17));
  const auto rays = testing::random_rays(3000, 19, scene.bounds());
  for (const char* spec : {"grid2", "grid2:exact=false", "grid2:mailbox=false", "grid2:top_density=0.3,leaf_density=4"}) {
    auto grid = make_accelerator(spec);
    grid->build(scene);
    expect_valid(*grid);
    expect_matches_brute_force(*grid, scene, rays, spec);
  }
}

TEST(TwoLevelGrid, RefinesTheDenseClusterOfATeapotInAStadium) {
  const Scene scene = Scene::from_mesh(teapot_in_stadium());
  auto grid2 = make_accelerator("grid2");
  grid2->build(scene);
  expect_valid(*grid2);
  // The cluster's top cell gets its own fine grid, so leaf cells far outnumber occupied top cells.
  EXPECT_GT(statistic(*grid2, "leaf_cells"), 10.0 * statistic(*grid2, "occupied_top_cells"));
  // Rays from the stadium toward the cluster.
  auto rays = testing::random_rays(2000, 23, AABB({-0.01f, -0.01f, -0.01f}, {0.01f, 0.01f, 0.01f}), 3000.0f);
  for (std::size_t i = 0; i < rays.size(); i += 2) rays[i].direction = Vec3{0.0f} - rays[i].origin;
  TraversalStats s2;
  for (const auto& r : rays) grid2->intersect(r, s2);
  auto grid = make_accelerator("grid");
  grid->build(scene);
  TraversalStats s1;
  for (const auto& r : rays) grid->intersect(r, s1);
  EXPECT_LT(s2.primitives_tested * 4, s1.primitives_tested);
  expect_matches_brute_force(*grid2, scene, rays, "stadium");
}

TEST(TwoLevelGrid, ClosedSphereAndQuadLattice) {
  const Scene sphere = Scene::from_mesh(testing::closed_sphere(30, 60));
  TwoLevelGrid grid;
  grid.build(sphere);
  expect_valid(grid);
  auto inside = testing::random_rays(1500, 29, AABB({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}), 1.0f);
  for (auto& r : inside) r.t_max = std::numeric_limits<float>::infinity();
  for (const auto& r : inside) EXPECT_TRUE(grid.occluded(r));
  expect_matches_brute_force(grid, sphere, inside, "sphere inside");

  const Scene lattice = Scene::from_mesh(testing::quad_lattice(4));
  for (const char* spec : {"grid2", "grid2:top_density=0.5,leaf_density=3", "grid2:exact=false"}) {
    auto accel = make_accelerator(spec);
    accel->build(lattice);
    expect_valid(*accel);
    expect_matches_brute_force(*accel, lattice, testing::rays_along_planes(4, [](int, int k) { return float(k); }),
                               spec);
    expect_matches_brute_force(*accel, lattice, testing::random_rays(1500, 31, lattice.bounds()), spec);
  }
}

TEST(TwoLevelGrid, BadOptionsAreErrors) {
  EXPECT_THROW(make_accelerator("grid2:leaf_density=-1"), Error);
  EXPECT_THROW(make_accelerator("grid2:top_density=0"), Error);
  EXPECT_THROW(make_accelerator("grid2:max_leaf_resolution=300"), Error);
  EXPECT_THROW(make_accelerator("grid2:density=2"), Error);
}

}  // namespace
}  // namespace rayaccel
