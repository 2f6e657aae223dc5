// Affine3: composition and inversion, the errors for singular and non-finite transforms, and the outward-rounded
// world box.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "rayaccel/core/error.h"
#include "rayaccel/instance/affine.h"

namespace rayaccel {
namespace {

Affine3 sample_transform() {
  return Affine3::translation(1.5, -2.0, 3.25) * Affine3::rotation({1.0f, 2.0f, 0.5f}, 0.7) *
         Affine3::scaling(2.0, -0.5, 1.25);
}

TEST(Affine, InverseUndoesTheTransform) {
  const Affine3 m = sample_transform();
  const Affine3 product = m.inverse() * m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(product(r, c), r == c ? 1.0 : 0.0, 1e-14) << r << "," << c;
  }
  EXPECT_NEAR(m.determinant(), 2.0 * -0.5 * 1.25, 1e-14);  // a mirror: negative determinant
}

TEST(Affine, RotationKeepsLengthsAndTurnsTheRightWay) {
  const Affine3 r = Affine3::rotation({0.0f, 0.0f, 2.0f}, std::numbers::pi / 2);
  const auto p = r.apply_point({1.0f, 0.0f, 0.0f});
  EXPECT_NEAR(p[0], 0.0, 1e-15);
  EXPECT_NEAR(p[1], 1.0, 1e-15);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-15);
  EXPECT_THROW(Affine3::rotation({0.0f, 0.0f, 0.0f}, 1.0), Error);
}

TEST(Affine, SingularAndNonFiniteTransformsHaveNoInverse) {
  try {
    (void)Affine3::scaling(1.0, 0.0, 1.0).inverse();
    FAIL() << "a flat transform was inverted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("singular"), std::string::npos) << e.what();
  }
  Affine3 nan = Affine3::identity();
  nan(1, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW((void)nan.inverse(), Error);
  EXPECT_THROW((void)Affine3::scaling(1e-300, 1e-300, 1.0).inverse(), Error);
}

TEST(Affine, WorldBoxContainsEveryMappedCornerAndEdgePoint) {
  const Affine3 m = sample_transform();
  const AABB box({-1.0f, 0.25f, -3.0f}, {2.0f, 0.75f, 1.0f});
  const AABB world = transform_box(m, box);
  for (int i = 0; i <= 8; ++i) {
    for (int j = 0; j <= 8; ++j) {
      for (int k = 0; k <= 8; ++k) {
        const Vec3 p{box.lo.x + (box.hi.x - box.lo.x) * float(i) / 8, box.lo.y + (box.hi.y - box.lo.y) * float(j) / 8,
                     box.lo.z + (box.hi.z - box.lo.z) * float(k) / 8};
        const auto q = m.apply_point(p);
        for (std::size_t a = 0; a < 3; ++a) {
          EXPECT_LE(double(world.lo[a]), q[a]);
          EXPECT_GE(double(world.hi[a]), q[a]);
        }
      }
    }
  }
  EXPECT_TRUE(transform_box(m, AABB::empty()).is_empty());
}

TEST(Affine, MappedRayKeepsItsParameter) {
  const Affine3 m = sample_transform();
  Ray world;
  world.origin = {0.5f, 1.0f, -2.0f};
  world.direction = {0.25f, -1.0f, 0.5f};
  world.t_min = 0.125f;
  world.t_max = 7.0f;
  const Ray local = transform_ray(m.inverse(), world);
  EXPECT_EQ(local.t_min, world.t_min);
  EXPECT_EQ(local.t_max, world.t_max);
  // The point at t = 3 on either ray is the same point.
  const Vec3 local_point = local.origin + local.direction * 3.0f;
  const auto back = m.apply_point(local_point);
  const Vec3 world_point = world.origin + world.direction * 3.0f;
  for (std::size_t a = 0; a < 3; ++a) EXPECT_NEAR(back[a], world_point[a], 1e-5);
}

}  // namespace
}  // namespace rayaccel
