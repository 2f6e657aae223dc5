// Unit tests of half-space clipping's output room (geometry/clip_polygon.h): a polygon that rounding left slightly
// non-convex can cross a plane more than twice and gain more than one vertex, up to clip_capacity(n) = 2n (the BSP
// tree's n + 1 buffers overflowed on the conference room).
#include <gtest/gtest.h>

#include <vector>

#include "rayaccel/geometry/clip_polygon.h"

namespace rayaccel {
namespace {

TEST(ClipPolygon, NonConvexInputNeedsMoreThanOneExtraVertex) {
  // A zigzag across x = 0.5: every edge crosses the plane.
  const std::vector<Vec3> zigzag = {{0, 0, 0}, {1, 1e-3f, 0}, {0, 2e-3f, 0}, {1, 3e-3f, 0}, {0, 4e-3f, 0}, {1, 5e-3f, 0}};
  const int n = int(zigzag.size());
  std::vector<Vec3> out(clip_capacity(zigzag.size()) + 4, Vec3{-7.0f});
  const int k = clip_polygon_to_halfspace(zigzag.data(), n, {1, 0, 0}, 0.5, out.data());
  EXPECT_GT(k, n + 1) << "the old n + 1 buffers were too small";
  EXPECT_LE(std::size_t(k), clip_capacity(zigzag.size()));
  for (std::size_t i = clip_capacity(zigzag.size()); i < out.size(); ++i) EXPECT_EQ(out[i], Vec3{-7.0f});
  for (int i = 0; i < k; ++i) EXPECT_LE(out[i].x, 0.5f);
}

TEST(ClipPolygon, ConvexInputGainsAtMostOneVertex) {
  const std::vector<Vec3> square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  std::vector<Vec3> out(clip_capacity(square.size()));
  EXPECT_EQ(clip_polygon_to_halfspace(square.data(), 4, normalize(Vec3{1, 1, 0}), 1.2, out.data()), 5);
}

}  // namespace
}  // namespace rayaccel
