// Capped hulls: a rotated cube and a lone triangle are recovered exactly (their faces fit under the cap), every
// plane is a support plane of the points, and the ray test agrees with a double-precision clip of the same planes
// away from their boundaries.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "point_clouds.h"
#include "rayaccel/bv/hull_volume.h"
#include "rayaccel/bv/kdop_volume.h"
#include "rayaccel/bv/tightness.h"
#include "../float_specials.h"

namespace rayaccel {
namespace {

using test_values::kInf;

std::vector<Vec3> rotated_cube(float side) {
  std::vector<Vec3> pts;
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner{side * float(i & 1), side * float((i >> 1) & 1), side * float((i >> 2) & 1)};
    pts.push_back(test::rotate_and_shift(corner, {1, 2, 3}, {5, -2, 1}));
  }
  return pts;
}

TEST(BvHull, RotatedCubeIsRecovered) {
  const HullVolume v = HullVolume::fit(rotated_cube(2.0f));
  EXPECT_LE(v.plane_count, std::uint32_t(HullVolume::kMaxPlanes));
  EXPECT_NEAR(v.surface_area(), 24.0f, 24.0f * 1e-4f);  // six faces of side 2, where the box alone is far larger
}

TEST(BvHull, LoneTriangleIsRecovered) {
  // Both sides of the plane and the three edges: the double-sided triangle (flat, like AABB::surface_area).
  const std::vector<Vec3> tri{{0.3f, -1.0f, 2.0f}, {2.0f, 0.5f, -1.0f}, {-1.0f, 1.5f, 0.25f}};
  const HullVolume v = HullVolume::fit(tri);
  EXPECT_EQ(v.plane_count, 5u);
  const double exact = length(cross(tri[1] - tri[0], tri[2] - tri[0]));  // twice the triangle's area
  EXPECT_NEAR(v.surface_area(), exact, exact * 1e-4);
}

TEST(BvHull, EveryPlaneTouchesThePoints) {
  // Support planes: each plane has a point within rounding of it (moving any plane in would drop a point).
  for (const auto& cloud : test::standard_clouds(4)) {
    const HullVolume v = HullVolume::fit(cloud.points);
    const Vec3 c = hull_reference_point(v.box);
    double scale = 0.0;
    for (const Vec3& p : cloud.points) scale = std::max(scale, double(max_component(abs(p - c))));
    for (std::uint32_t i = 0; i < v.plane_count; ++i) {
      double support = -std::numeric_limits<double>::infinity();
      for (const Vec3& p : cloud.points) {
        const Vec3 n = v.planes.normal(int(i));
        support = std::max(support, double(n.x) * (double(p.x) - c.x) + double(n.y) * (double(p.y) - c.y) +
                                        double(n.z) * (double(p.z) - c.z));
      }
      EXPECT_LE(support, v.planes.offset[i]) << cloud.name;
      EXPECT_GE(support, v.planes.offset[i] - 1e-5 * (scale + 1e-30)) << cloud.name;
    }
  }
}

/// The line's parameter interval inside box ∩ planes with every face moved out by `grow`, clipped in double (the
/// reference for the float test). False when the line misses.
bool reference_interval(const HullVolume& v, const Ray& ray, double grow, double& t0, double& t1) {
  t0 = -std::numeric_limits<double>::infinity();
  t1 = std::numeric_limits<double>::infinity();
  const auto clip = [&](double o, double d, double offset) {  // o + t d <= offset
    if (d == 0.0) return o <= offset;
    const double t = (offset - o) / d;
    if (d > 0.0) t1 = std::min(t1, t);
    else t0 = std::max(t0, t);
    return true;
  };
  for (int a = 0; a < 3; ++a) {
    if (!clip(ray.origin[a], ray.direction[a], double(v.box.hi[a]) + grow)) return false;
    if (!clip(-double(ray.origin[a]), -double(ray.direction[a]), -double(v.box.lo[a]) + grow)) return false;
  }
  const Vec3 c = hull_reference_point(v.box);
  for (std::uint32_t i = 0; i < v.plane_count; ++i) {
    const Vec3 n = v.planes.normal(int(i));
    const double o = double(n.x) * (double(ray.origin.x) - c.x) + double(n.y) * (double(ray.origin.y) - c.y) +
                     double(n.z) * (double(ray.origin.z) - c.z);
    const double d = double(n.x) * ray.direction.x + double(n.y) * ray.direction.y + double(n.z) * ray.direction.z;
    if (!clip(o, d, double(v.planes.offset[i]) + grow)) return false;
  }
  return t0 <= t1;
}

TEST(BvHull, RayTestMatchesADoubleClipAwayFromTheBoundary) {
  std::mt19937 rng(17);
  int hits = 0, misses = 0;
  for (const auto& cloud : test::standard_clouds(5)) {
    const HullVolume v = HullVolume::fit(cloud.points);
    const AABB b = v.bounds();
    const Vec3 size = b.hi - b.lo;
    const double diagonal = length(size);
    if (!(diagonal > 0.0) || !std::isfinite(diagonal) || diagonal > 1e6) continue;
    for (int i = 0; i < 2000; ++i) {
      const Vec3 from = test::random_in_box(rng, b.lo - size, b.hi + size);
      const Vec3 to = test::random_in_box(rng, b.lo - 0.2f * size, b.hi + 0.2f * size);
      const Ray ray{from, (i % 3 == 0) ? 0.5f : -kInf, to - from, (i % 5 == 0) ? 0.7f : kInf};
      const PreparedRay prepared(ray);
      float entry;
      const bool got = v.intersect(HullVolume::prepare(prepared), prepared.t_min, prepared.t_max, &entry);
      double t0, t1;
      if (reference_interval(v, ray, 0.0, t0, t1) && t0 <= ray.t_max && t1 >= ray.t_min) {
        ASSERT_TRUE(got) << cloud.name << " ray " << i;
        EXPECT_LE(entry, std::max(t0, double(ray.t_min)) + 1e-5 * (1.0 + std::fabs(t0))) << cloud.name;
        ++hits;
        continue;
      }
      // A clear miss, by 1e-4 of the diagonal in space (faces moved out) and in t: the test must reject it.
      const double margin = 1e-4;
      if (!reference_interval(v, ray, margin * diagonal, t0, t1) || t0 > ray.t_max + margin ||
          t1 < ray.t_min - margin) {
        EXPECT_FALSE(got) << cloud.name << " ray " << i;
        ++misses;
      }
    }
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(misses, 1000);
}

TEST(BvHull, TighterThanTheKdop26OnALongDiagonalSliver) {
  // A thin sliver along (1, 2, 3): the box and the fixed k-DOP directions cannot follow it, the hull's planes can.
  std::vector<Vec3> pts;
  std::mt19937 rng(3);
  for (int i = 0; i < 200; ++i) {
    const Vec3 p = test::random_in_box(rng, {-0.05f, -0.05f, 0}, {0.05f, 0.05f, 10});
    pts.push_back(test::rotate_and_shift(p, {1, 2, 3}, {}));
  }
  const double hull = convex_hull_measure(pts).area;
  const HullVolume v = HullVolume::fit(pts);
  EXPECT_LT(v.surface_area(), Kdop26Volume::fit(pts).surface_area());
  EXPECT_LT(v.surface_area(), 1.5 * hull);
  EXPECT_GE(v.surface_area(), hull * (1.0 - 1e-5));
}

}  // namespace
}  // namespace rayaccel
