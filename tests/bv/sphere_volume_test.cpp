// Bounding-sphere fitting: exact minimum spheres of small sets (Welzl) and near-minimal ones of large sets (EPOS-26).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "point_clouds.h"
#include "rayaccel/bv/sphere_volume.h"

namespace rayaccel {
namespace {

TEST(BvSphere, TwoPointsGiveTheDiameterSphere) {
  const std::vector<Vec3> pts{{-1, 2, 3}, {3, 2, 3}};
  const SphereVolume s = SphereVolume::fit(pts);
  EXPECT_NEAR(s.center.x, 1.0f, 1e-6f);
  EXPECT_NEAR(s.radius, 2.0f, 1e-5f);
}

TEST(BvSphere, AcuteTriangleGivesItsCircumcircle) {
  const float h = std::sqrt(3.0f);
  const std::vector<Vec3> pts{{-1, 0, 5}, {1, 0, 5}, {0, h, 5}};
  const SphereVolume s = SphereVolume::fit(pts);
  EXPECT_NEAR(s.radius, 2.0f / h, 1e-5f);
  EXPECT_NEAR(s.center.y, h / 3.0f, 1e-5f);
}

TEST(BvSphere, ObtuseTriangleGivesItsLongestEdgeSphere) {
  const std::vector<Vec3> pts{{-2, 0, 0}, {2, 0, 0}, {0.5f, 0.3f, 0}};
  const SphereVolume s = SphereVolume::fit(pts);
  EXPECT_NEAR(s.radius, 2.0f, 1e-5f);
  EXPECT_NEAR(s.center.x, 0.0f, 1e-6f);
}

TEST(BvSphere, RegularTetrahedronGivesItsCircumsphere) {
  const std::vector<Vec3> pts{{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}, {0, 0, 0.1f}};
  const SphereVolume s = SphereVolume::fit(pts);
  EXPECT_NEAR(s.radius, std::sqrt(3.0f), 1e-5f);
}

TEST(BvSphere, CoplanarAndCollinearSmallSetsAreExact) {
  // Four cocircular points (a square) and a collinear run: degenerate support sets for Welzl.
  const std::vector<Vec3> square{{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}, {0.5f, 0.5f, 0}};
  EXPECT_NEAR(SphereVolume::fit(square).radius, 1.0f, 1e-5f);
  const std::vector<Vec3> line{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {0.5f, 0.5f, 0.5f}, {3, 3, 3}};
  EXPECT_NEAR(SphereVolume::fit(line).radius, 1.5f * std::sqrt(3.0f), 1e-5f);
}

TEST(BvSphere, LargeSetsAreWithinTwoPercentOfTheMinimum) {
  // Points on the unit sphere (the minimum sphere is the unit sphere) and in a box (minimum: the half diagonal,
  // reached by the corners, which are included).
  std::mt19937 rng(3);
  std::normal_distribution<float> g;
  std::vector<Vec3> sphere_pts;
  for (int i = 0; i < 2000; ++i) sphere_pts.push_back(normalize(Vec3{g(rng), g(rng), g(rng)}));
  const SphereVolume s = SphereVolume::fit(sphere_pts);
  EXPECT_LE(s.radius, 1.02f);
  EXPECT_GE(s.radius, 0.999f);
  std::vector<Vec3> box_pts;
  for (int i = 0; i < 8; ++i) box_pts.push_back({i & 1 ? 2.0f : -2.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 0.5f : -0.5f});
  for (int i = 0; i < 500; ++i) box_pts.push_back(test::random_in_box(rng, {-2, -1, -0.5f}, {2, 1, 0.5f}));
  EXPECT_LE(SphereVolume::fit(box_pts).radius, 1.02f * std::sqrt(4.0f + 1.0f + 0.25f));
}

TEST(BvSphere, MeasuresAndBounds) {
  const SphereVolume s = SphereVolume::fit(std::vector<Vec3>{{0, 0, -1}, {0, 0, 1}});
  EXPECT_NEAR(s.surface_area(), 4.0f * 3.14159265f, 1e-4f);
  EXPECT_NEAR(s.volume(), 4.0f / 3.0f * 3.14159265f, 1e-4f);
  const AABB b = s.bounds();
  EXPECT_LE(b.hi.x, 1.0001f);
  EXPECT_GE(b.hi.x, 1.0f);
  EXPECT_FALSE(s.contains({0.8f, 0.8f, 0}));
}

}  // namespace
}  // namespace rayaccel
