// OBB fitting: a rotated box is recovered, thin rotated slivers get far less area than their AABB, and the fit never
// does worse than the AABB.
#include <gtest/gtest.h>

#include <random>

#include "point_clouds.h"
#include "rayaccel/bv/aabb_volume.h"
#include "rayaccel/bv/obb_volume.h"

namespace rayaccel {
namespace {

std::vector<Vec3> rotated_box_points(std::mt19937& rng, const Vec3& half, const Vec3& normal, int interior) {
  std::vector<Vec3> pts;
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner{i & 1 ? half.x : -half.x, i & 2 ? half.y : -half.y, i & 4 ? half.z : -half.z};
    pts.push_back(test::rotate_and_shift(corner, normal, {3, -2, 1}));
  }
  for (int i = 0; i < interior; ++i)
    pts.push_back(test::rotate_and_shift(test::random_in_box(rng, -half, half), normal, {3, -2, 1}));
  std::shuffle(pts.begin(), pts.end(), rng);
  return pts;
}

TEST(BvObb, RecoversARotatedBox) {
  std::mt19937 rng(9);
  const Vec3 half{3.0f, 1.0f, 0.25f};
  const float area = 8.0f * (half.x * half.y + half.y * half.z + half.z * half.x);
  for (const Vec3& normal : {Vec3{0.2f, 0.5f, 0.9f}, Vec3{-0.7f, 0.1f, 0.3f}, Vec3{1, 1, 1}}) {
    for (int interior : {0, 20, 2000}) {
      const ObbVolume v = ObbVolume::fit(rotated_box_points(rng, half, normal, interior));
      EXPECT_LE(v.surface_area(), 1.02f * area) << interior;
      EXPECT_GE(v.surface_area(), 0.999f * area) << interior;
    }
  }
}

TEST(BvObb, ThinRotatedSliverBeatsTheAabb) {
  for (const auto& cloud : test::standard_clouds(2)) {
    if (cloud.name != "sliver" && cloud.name != "flat_rotated") continue;
    const float obb = ObbVolume::fit(cloud.points).surface_area();
    const float aabb = AabbVolume::fit(cloud.points).surface_area();
    EXPECT_LT(obb, 0.6f * aabb) << cloud.name;
  }
}

TEST(BvObb, NeverWorseThanTheAabb) {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    for (const auto& cloud : test::standard_clouds(seed)) {
      const float obb = ObbVolume::fit(cloud.points).surface_area();
      // The AABB grown by the fit margin every fitted volume carries (4 ulps of the largest coordinate, per side).
      AABB box = AabbVolume::fit(cloud.points).box;
      const float margin = 8.0f * 0x1p-22f * std::max(max_component(abs(box.lo)), max_component(abs(box.hi)));
      box.lo -= Vec3(margin);
      box.hi += Vec3(margin);
      EXPECT_LE(obb, box.surface_area() * (1.0f + 1e-5f)) << cloud.name;
    }
  }
}

TEST(BvObb, FitWithAxesUsesTheGivenFrame) {
  const std::vector<Vec3> pts{{0, 0, 0}, {1, 1, 0}, {2, 2, 0}, {1, 1, 1}};
  const ObbVolume v = ObbVolume::fit_with_axes(pts, {1, 1, 0}, {0, 0, 1});
  EXPECT_NEAR(std::fabs(v.box.axis[0].x), std::sqrt(0.5f), 1e-6f);
  EXPECT_NEAR(v.box.half.x, std::sqrt(2.0f), 1e-5f);
  EXPECT_NEAR(v.box.half.y, 0.5f, 1e-5f);
  EXPECT_NEAR(v.box.half.z, 0.0f, 1e-5f);
  for (const Vec3& p : pts) EXPECT_TRUE(v.contains(p));
  EXPECT_FALSE(v.contains({2, 0, 0}));
}

TEST(BvObb, BoundsEncloseTheCorners) {
  std::mt19937 rng(4);
  const auto pts = rotated_box_points(rng, {2, 1, 0.5f}, {0.3f, 0.4f, 0.5f}, 0);
  const ObbVolume v = ObbVolume::fit(pts);
  AABB exact;
  for (const Vec3& p : pts) exact.extend(p);
  const AABB b = v.bounds();
  EXPECT_TRUE(b.contains(exact));
  EXPECT_LE(b.surface_area(), exact.surface_area() * 1.02f);
}

}  // namespace
}  // namespace rayaccel
