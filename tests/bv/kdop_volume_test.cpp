// k-DOPs: the fitted slabs of a cube, exact polytope area and volume, the tightness order 26 <= 14/18 <= AABB, and
// the kernel on rays with zero projection on a diagonal.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "point_clouds.h"
#include "rayaccel/bv/aabb_volume.h"
#include "rayaccel/bv/kdop_volume.h"
#include "rayaccel/bv/tightness.h"

namespace rayaccel {
namespace {

std::vector<Vec3> unit_cube_corners() {
  std::vector<Vec3> pts;
  for (int i = 0; i < 8; ++i) pts.push_back({float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
  return pts;
}

template <int K>
void expect_cube_planes() {
  const KdopVolume<K> v = KdopVolume<K>::fit(unit_cube_corners());
  constexpr auto dirs = kdop_directions<K>();
  for (int j = 0; j < K / 2; ++j) {
    // Each slab spans the min and max of dot(dir, corner) over the corners: the sums of negative / positive entries.
    float lo = 0, hi = 0;
    for (int a = 0; a < 3; ++a) (dirs[j][a] < 0 ? lo : hi) += dirs[j][a];
    EXPECT_NEAR(v.lo[j], lo, 1e-6f) << K << " slab " << j;
    EXPECT_NEAR(v.hi[j], hi, 1e-6f) << K << " slab " << j;
  }
  EXPECT_NEAR(v.surface_area(), 6.0f, 1e-4f);
  EXPECT_NEAR(v.volume(), 1.0f, 1e-4f);
}

TEST(BvKdop, CubeGivesTheCubePlanes) {
  expect_cube_planes<14>();
  expect_cube_planes<18>();
  expect_cube_planes<26>();
}

TEST(BvKdop, OctahedronAreaAndVolumeAreExact) {
  // The 14-DOP of an octahedron's vertices is the octahedron: area 4 sqrt(3), volume 4/3.
  const std::vector<Vec3> pts{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const Kdop14Volume v = Kdop14Volume::fit(pts);
  EXPECT_NEAR(v.surface_area(), 4.0f * std::sqrt(3.0f), 1e-4f);
  EXPECT_NEAR(v.volume(), 4.0f / 3.0f, 1e-4f);
  EXPECT_NEAR(v.surface_area(), float(convex_hull_measure(pts).area), 1e-4f);
}

TEST(BvKdop, FlatSetHasDoubleSidedArea) {
  const std::vector<Vec3> pts{{0, 0, 2}, {1, 0, 2}, {1, 1, 2}, {0, 1, 2}};
  const Kdop26Volume v = Kdop26Volume::fit(pts);
  EXPECT_NEAR(v.surface_area(), 2.0f, 1e-4f);
  EXPECT_NEAR(v.volume(), 0.0f, 1e-4f);
}

TEST(BvKdop, MoreSlabsAreTighter) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    for (const auto& cloud : test::standard_clouds(seed)) {
      if (cloud.name == "tiny" || cloud.points.size() < 4) continue;
      const float aabb_v = AabbVolume::fit(cloud.points).box.volume();
      const float aabb_a = AabbVolume::fit(cloud.points).surface_area();
      const Kdop14Volume k14 = Kdop14Volume::fit(cloud.points);
      const Kdop18Volume k18 = Kdop18Volume::fit(cloud.points);
      const Kdop26Volume k26 = Kdop26Volume::fit(cloud.points);
      const float tol = 1.0f + 1e-4f;
      // Flat sets have volume 0 up to the fit margin times their area.
      const float flat = 1e-5f * aabb_a * std::sqrt(aabb_a);
      EXPECT_LE(k26.volume(), k14.volume() * tol + flat) << cloud.name;
      EXPECT_LE(k26.volume(), k18.volume() * tol + flat) << cloud.name;
      EXPECT_LE(k14.volume(), aabb_v * tol + flat) << cloud.name;
      EXPECT_LE(k18.volume(), aabb_v * tol + flat) << cloud.name;
      EXPECT_LE(k26.surface_area(), k14.surface_area() * tol) << cloud.name;
      EXPECT_LE(k14.surface_area(), aabb_a * tol) << cloud.name;
      EXPECT_LE(k18.surface_area(), aabb_a * tol) << cloud.name;
    }
  }
  // On a random solid set the diagonals cut real corners off the box.
  const auto clouds = test::standard_clouds(1);
  const auto& pts = clouds[2].points;
  EXPECT_LT(Kdop26Volume::fit(pts).volume(), 0.95f * AabbVolume::fit(pts).box.volume());
}

TEST(BvKdop, RayWithZeroDiagonalProjection) {
  // Direction (1, -1, 0) is parallel to the (1, 1, 0) slab: it is then decided by the origin's projection alone.
  const Kdop18Volume v = Kdop18Volume::fit(unit_cube_corners());
  const float inf = std::numeric_limits<float>::infinity();
  const PreparedRay inside(Ray{{-1, 2, 0.5f}, 0, {1, -1, 0}, inf});   // x + y = 1: inside [0, 2]
  const PreparedRay on_plane(Ray{{-1, 3, 0.5f}, 0, {1, -1, -0.0f}, inf});  // x + y = 2: on the hi plane
  const PreparedRay outside(Ray{{-1, 3.01f, 0.5f}, 0, {1, -1, 0}, inf});  // x + y > 2
  float entry;
  EXPECT_TRUE(v.intersect(Kdop18Volume::prepare(inside), 0, inf, &entry));
  EXPECT_NEAR(entry, 1.0f, 1e-5f);
  EXPECT_TRUE(v.intersect(Kdop18Volume::prepare(on_plane), 0, inf, &entry));
  EXPECT_FALSE(v.intersect(Kdop18Volume::prepare(outside), 0, inf, &entry));
}

}  // namespace
}  // namespace rayaccel
