// Quickhull area and volume on solids with known measures, lattices full of coplanar points, flat, collinear and
// duplicate sets; and the tightness sums built on it.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "point_clouds.h"
#include "rayaccel/bv/aabb_volume.h"
#include "rayaccel/bv/obb_volume.h"
#include "rayaccel/bv/tightness.h"

namespace rayaccel {
namespace {

TEST(BvConvexHull, BoxWithInteriorPoints) {
  std::mt19937 rng(1);
  std::vector<Vec3> pts;
  for (int i = 0; i < 8; ++i) pts.push_back({i & 1 ? 2.0f : 0.0f, i & 2 ? 3.0f : 0.0f, i & 4 ? 1.0f : 0.0f});
  for (int i = 0; i < 500; ++i) pts.push_back(test::random_in_box(rng, {0, 0, 0}, {2, 3, 1}));
  std::shuffle(pts.begin(), pts.end(), rng);
  const HullMeasure m = convex_hull_measure(pts);
  EXPECT_NEAR(m.area, 2.0 * (6 + 3 + 2), 1e-9);
  EXPECT_NEAR(m.volume, 6.0, 1e-9);
}

TEST(BvConvexHull, LatticeFullOfCoplanarPoints) {
  std::vector<Vec3> pts;
  for (int x = 0; x < 6; ++x)
    for (int y = 0; y < 6; ++y)
      for (int z = 0; z < 6; ++z) pts.push_back({float(x), float(y), float(z)});
  const HullMeasure m = convex_hull_measure(pts);
  EXPECT_NEAR(m.area, 6.0 * 25.0, 1e-9);
  EXPECT_NEAR(m.volume, 125.0, 1e-9);
}

TEST(BvConvexHull, SpherePointsApproachTheSphere) {
  std::mt19937 rng(2);
  std::normal_distribution<float> g;
  std::vector<Vec3> pts;
  for (int i = 0; i < 3000; ++i) pts.push_back(normalize(Vec3{g(rng), g(rng), g(rng)}) * 2.0f);
  const HullMeasure m = convex_hull_measure(pts);
  const double area = 4.0 * std::numbers::pi * 4.0;
  EXPECT_LT(m.area, area);
  EXPECT_GT(m.area, 0.99 * area);
  EXPECT_GT(m.volume, 0.98 * 4.0 / 3.0 * std::numbers::pi * 8.0);
}

TEST(BvConvexHull, DegenerateSets) {
  EXPECT_EQ(convex_hull_measure({}).area, 0.0);
  const std::vector<Vec3> one{{1, 2, 3}};
  EXPECT_EQ(convex_hull_measure(one).area, 0.0);
  const std::vector<Vec3> same{{1, 2, 3}, {1, 2, 3}, {1, 2, 3}, {1, 2, 3}};
  EXPECT_EQ(convex_hull_measure(same).area, 0.0);
  const std::vector<Vec3> line{{0, 0, 0}, {1, 1, 1}, {3, 3, 3}, {2, 2, 2}};
  EXPECT_EQ(convex_hull_measure(line).area, 0.0);
  // A flat unit square (with points on its edges and inside) counts both sides, like a flat AABB.
  const std::vector<Vec3> square{{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}, {0.5f, 0, 1}, {0.5f, 0.5f, 1}};
  EXPECT_NEAR(convex_hull_measure(square).area, 2.0, 1e-12);
  EXPECT_EQ(convex_hull_measure(square).volume, 0.0);
  // A tetrahedron given with every vertex three times.
  std::vector<Vec3> tetra;
  for (int r = 0; r < 3; ++r)
    for (const Vec3& p : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}) tetra.push_back(p);
  EXPECT_NEAR(convex_hull_measure(tetra).area, 1.5 + std::sqrt(3.0) / 2.0, 1e-12);
  EXPECT_NEAR(convex_hull_measure(tetra).volume, 1.0 / 6.0, 1e-12);
}

TEST(BvConvexHull, HullNeverExceedsAnEnclosingBox) {
  for (const auto& cloud : test::standard_clouds(5)) {
    const HullMeasure m = convex_hull_measure(cloud.points);
    AABB box;
    for (const Vec3& p : cloud.points) box.extend(p);
    EXPECT_LE(float(m.area), box.surface_area() * (1 + 1e-6f)) << cloud.name;
    EXPECT_GE(m.area, 0.0) << cloud.name;
  }
}

TEST(BvTightness, SumsGiveAreaRatios) {
  const std::vector<Vec3> sliver = test::standard_clouds(1)[9].points;
  ASSERT_EQ(test::standard_clouds(1)[9].name, "sliver");
  const TightnessSums aabb = tightness_of<AabbVolume>(sliver);
  EXPECT_NEAR(aabb.over_aabb(), 1.0, 1e-6);
  EXPECT_GT(aabb.over_hull(), 1.0);
  const TightnessSums obb = tightness_of<ObbVolume>(sliver);
  EXPECT_LT(obb.over_aabb(), 0.6);
  EXPECT_GE(obb.over_hull(), 1.0);
  EXPECT_LT(obb.over_hull(), aabb.over_hull());
  TightnessSums none;
  none.add(5.0, sliver, false);
  EXPECT_EQ(none.over_hull(), 0.0);
  EXPECT_GT(none.over_aabb(), 0.0);
}

}  // namespace
}  // namespace rayaccel
