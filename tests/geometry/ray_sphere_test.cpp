// Unit tests of the ray/sphere kernel (geometry/ray_sphere.h, Haines et al. 2019): outside, inside, tangent-ish and
// behind, the t range rule, (u, v) parameterisation, precision far away, and void rays.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "rayaccel/geometry/ray_sphere.h"
#include "../float_specials.h"

namespace rayaccel {
namespace {

using test_values::kInf;

bool hit_sphere(const Ray& ray, const Vec3& center, float radius, Hit* out = nullptr) {
  const PreparedRay r(ray);
  Hit hit = Hit::begin(r);
  const bool found = intersect_sphere(r, center, radius, 3, hit);
  if (out) *out = hit;
  return found;
}

TEST(RaySphere, FromOutsideHitsTheNearSide) {
  Hit hit;
  ASSERT_TRUE(hit_sphere(Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, kInf}, {0, 0, 5}, 1.0f, &hit));
  EXPECT_FLOAT_EQ(hit.t, 4.0f);
  EXPECT_EQ(hit.prim_id, 3u);
  ASSERT_TRUE(hit_sphere(Ray{{0, 0, 0}, 0.0f, {0, 0, 2}, kInf}, {0, 0, 5}, 1.0f, &hit));
  EXPECT_FLOAT_EQ(hit.t, 2.0f) << "t is in units of the direction's length";
}

TEST(RaySphere, FromInsideHitsTheFarSide) {
  Hit hit;
  ASSERT_TRUE(hit_sphere(Ray{{0, 0, 5}, 0.0f, {0, 1, 0}, kInf}, {0, 0, 5}, 2.0f, &hit));
  EXPECT_FLOAT_EQ(hit.t, 2.0f);
  ASSERT_TRUE(hit_sphere(Ray{{0, 0.5f, 5}, 0.0f, {0, -1, 0}, kInf}, {0, 0, 5}, 2.0f, &hit));
  EXPECT_FLOAT_EQ(hit.t, 2.5f);
}

TEST(RaySphere, BehindTheOriginIsMissed) {
  EXPECT_FALSE(hit_sphere(Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, kInf}, {0, 0, -5}, 1.0f));
  EXPECT_TRUE(hit_sphere(Ray{{0, 0, 0}, -kInf, {0, 0, 1}, kInf}, {0, 0, -5}, 1.0f)) << "unless t_min allows it";
}

TEST(RaySphere, NearlyTangentRays) {
  EXPECT_TRUE(hit_sphere(Ray{{0.999f, 0, 0}, 0.0f, {0, 0, 1}, kInf}, {0, 0, 5}, 1.0f));
  EXPECT_FALSE(hit_sphere(Ray{{1.001f, 0, 0}, 0.0f, {0, 0, 1}, kInf}, {0, 0, 5}, 1.0f));
  EXPECT_FALSE(hit_sphere(Ray{{0, 1.0001f, 0}, 0.0f, {0, 0, 1}, kInf}, {0, 0, 5}, 1.0f));
  Hit hit;
  ASSERT_TRUE(hit_sphere(Ray{{0, 0.9999f, 0}, 0.0f, {0, 0, 1}, kInf}, {0, 0, 5}, 1.0f, &hit));
  EXPECT_NEAR(hit.t, 5.0f, 0.02f);
}

TEST(RaySphere, RespectsTheTRange) {
  const Vec3 center{0, 0, 5};
  Hit hit;
  EXPECT_TRUE(hit_sphere(Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, 4.0f}, center, 1.0f)) << "t == t_max counts";
  EXPECT_FALSE(hit_sphere(Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, 3.9f}, center, 1.0f));
  ASSERT_TRUE(hit_sphere(Ray{{0, 0, 0}, 4.0f, {0, 0, 1}, kInf}, center, 1.0f, &hit)) << "t == t_min skips to far";
  EXPECT_FLOAT_EQ(hit.t, 6.0f);
  EXPECT_FALSE(hit_sphere(Ray{{0, 0, 0}, 6.0f, {0, 0, 1}, kInf}, center, 1.0f));
}

TEST(RaySphere, UVFollowLongitudeAndLatitude) {
  Hit hit;
  ASSERT_TRUE(hit_sphere(Ray{{0, 5, 0}, 0.0f, {0, -1, 0}, kInf}, {0, 0, 0}, 1.0f, &hit));
  EXPECT_NEAR(hit.v, 0.0f, 1e-6f) << "north pole";
  ASSERT_TRUE(hit_sphere(Ray{{5, 0, 0}, 0.0f, {-1, 0, 0}, kInf}, {0, 0, 0}, 1.0f, &hit));
  EXPECT_NEAR(hit.u, 0.0f, 1e-6f);
  EXPECT_NEAR(hit.v, 0.5f, 1e-6f) << "equator";
  ASSERT_TRUE(hit_sphere(Ray{{0, 0, 5}, 0.0f, {0, 0, -1}, kInf}, {0, 0, 0}, 1.0f, &hit));
  EXPECT_NEAR(hit.u, 0.25f, 1e-6f);
}

TEST(RaySphere, PreciseForSmallDistantSpheres) {
  Hit hit;
  ASSERT_TRUE(hit_sphere(Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, kInf}, {0, 0, 1e5f}, 0.01f, &hit));
  EXPECT_FLOAT_EQ(hit.t, 1e5f - 0.01f);
  EXPECT_FALSE(hit_sphere(Ray{{0.0101f, 0, 0}, 0.0f, {0, 0, 1}, kInf}, {0, 0, 1e5f}, 0.01f));
}

TEST(RaySphere, VoidRaysNeverHit) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const Ray& ray : {Ray{{nan, 0, 0}, 0.0f, {0, 0, 1}, kInf}, Ray{{0, 0, 0}, 0.0f, {0, 0, 0}, kInf},
                         Ray{{0, 0, 0}, 0.0f, {0, 0, kInf}, kInf}, Ray{{0, 0, 0}, 7.0f, {0, 0, 1}, 3.0f},
                         Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, nan}}) {
    EXPECT_FALSE(hit_sphere(ray, {0, 0, 5}, 1.0f));
  }
}

}  // namespace
}  // namespace rayaccel
