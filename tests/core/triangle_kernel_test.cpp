// Unit tests of the watertight ray/triangle kernel.
#include <gtest/gtest.h>

#include "rayaccel/geometry/ray_triangle.h"

namespace rayaccel {
namespace {

TEST(RayTriangle, HitsCenterWithEmbreeBarycentrics) {
  const Vec3 v0{0, 0, 0}, v1{1, 0, 0}, v2{0, 1, 0};
  Ray ray{{0.25f, 0.5f, -1.0f}, 0.0f, {0, 0, 1}, 10.0f};
  PreparedRay pr(ray);
  Hit hit = Hit::begin(pr);
  ASSERT_TRUE(intersect_triangle(pr, v0, v1, v2, 7, hit));
  EXPECT_FLOAT_EQ(hit.t, 1.0f);
  EXPECT_EQ(hit.prim_id, 7u);
  EXPECT_FLOAT_EQ(hit.u, 0.25f);
  EXPECT_FLOAT_EQ(hit.v, 0.5f);
}

}  // namespace
}  // namespace rayaccel
