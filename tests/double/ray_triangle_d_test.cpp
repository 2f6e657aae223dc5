// The double watertight kernel (geometry/ray_triangle_d.h, after Woop, Benthin, Wald 2013) against exact rational
// arithmetic on the double inputs (exact_reference_d.h): the same hit or miss on every ray aimed at vertices, edges
// and centres of triangles at scales from 1e-15 to 1e15 and far from the origin, t and barycentrics within a few ulps
// of the exact ones; void rays and the t range; DoubleScene's checks.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "../error_message.h"
#include "double_test_rays.h"
#include "exact_reference_d.h"
#include "rayaccel/double/double_scene.h"
#include "rayaccel/geometry/ray_triangle_d.h"

namespace rayaccel {
namespace {

using exact_d::exact_hits;

/// Kernel answer for one triangle over the ray's whole (t_min, t_max].
HitD kernel_hit(const RayD& ray, const std::array<DVec3, 3>& t) {
  const PreparedRayD r(ray);
  HitD hit = HitD::begin(r);
  intersect_triangle(r, t[0], t[1], t[2], 0, hit);
  hit.finish();
  return hit;
}

/// A triangle of size `size` at `offset`, and rays from 2 to 5 sizes away aimed exactly at its vertices, at double
/// points on its edges, at its centroid and just beside the edges: kernel and exact reference agree on every one.
void check_scale(double size, double offset, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), fraction(0.0, 1.0);
  int hits = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const DVec3 base{offset + size * unit(rng), offset * 0.5 + size * unit(rng), -offset + size * unit(rng)};
    const std::array<DVec3, 3> tri{base, base + DVec3{size * fraction(rng), size * unit(rng), size * unit(rng) * 0.3},
                                   base + DVec3{size * unit(rng) * 0.3, size * fraction(rng), size * unit(rng)}};
    DVec3 target;
    switch (trial % 5) {
      case 0: target = tri[trial % 3]; break;
      case 1: target = tri[0] + (tri[1] - tri[0]) * fraction(rng); break;  // on an edge, or an ulp beside it
      case 2: target = tri[1] + (tri[2] - tri[1]) * 0.5; break;
      case 3: target = (tri[0] + tri[1] + tri[2]) * (1.0 / 3.0); break;
      default: target = tri[2] + (tri[2] - tri[0]) * 1e-12; break;  // just beyond a vertex
    }
    RayD ray;
    ray.origin = target + testing::random_unit(rng) * (size * (2.0 + 3.0 * fraction(rng)));
    ray.direction = target - ray.origin;
    if (!is_valid_ray(ray)) continue;  // a direction component below 2^-64: void by the domain rule
    const auto exact = exact_hits({tri}, ray);
    const HitD hit = kernel_hit(ray, tri);
    ASSERT_EQ(hit.found(), !exact.empty()) << "size " << size << " offset " << offset << " trial " << trial;
    if (exact.empty()) continue;
    ++hits;
    // t near 1 (the target is one direction length away); the kernel's t is within a few ulps of the distances.
    EXPECT_NEAR(hit.t, exact[0].t, 1e-11) << "trial " << trial;
    EXPECT_NEAR(hit.u, exact[0].u, 1e-9) << "trial " << trial;
    EXPECT_NEAR(hit.v, exact[0].v, 1e-9) << "trial " << trial;
  }
  EXPECT_GT(hits, 100);
}

TEST(DoubleKernel, MatchesExactReferenceAtEveryScale) {
  check_scale(1.0, 0.0, 1);
  check_scale(1e-15, 1e-12, 2);
  check_scale(1e15, 0.0, 3);
  check_scale(0.01, 1e7, 4);   // centimetre triangles near 1e7
  check_scale(1.0, 1e12, 5);
}

TEST(DoubleKernel, EdgeFunctionsRoundingToZeroAreDecidedExactly) {
  // Rays from 1,000 units away through the double nearest to a point of an edge: the ray passes within about 1e-17
  // of the edge, far inside the double edge function's error bound, on one side or the other or exactly on it. Only
  // the exact fallback gets these right (on the edge or inside: a hit); both outcomes occur.
  const std::array<DVec3, 3> tri{DVec3{0.1, 0.2, 0.3}, DVec3{1.7, 0.9, 0.35}, DVec3{0.2, 1.9, 0.31}};
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> fraction(0.01, 0.99);
  int hits = 0, misses = 0;
  for (int i = 0; i < 400; ++i) {
    const DVec3 target = tri[i % 3] + (tri[(i + 1) % 3] - tri[i % 3]) * fraction(rng);
    RayD ray;
    ray.origin = target + testing::random_unit(rng) * 1000.0;
    ray.direction = target - ray.origin;
    const auto exact = exact_hits({tri}, ray);
    const HitD hit = kernel_hit(ray, tri);
    ASSERT_EQ(hit.found(), !exact.empty()) << "ray " << i;
    (exact.empty() ? misses : hits)++;
  }
  EXPECT_GT(hits, 40);
  EXPECT_GT(misses, 40);
}

TEST(DoubleKernel, HonoursTheTRangeAndRejectsVoidRays) {
  const std::array<DVec3, 3> tri{DVec3{-1, -1, 5}, DVec3{1, -1, 5}, DVec3{0, 1, 5}};
  RayD ray;  // from the origin along +z: hits at t = 5
  EXPECT_DOUBLE_EQ(kernel_hit(ray, tri).t, 5.0);
  ray.t_max = 5.0;  // t <= t_max counts
  EXPECT_TRUE(kernel_hit(ray, tri).found());
  ray.t_max = std::nextafter(5.0, 0.0);
  EXPECT_FALSE(kernel_hit(ray, tri).found());
  ray.t_max = 10.0;
  ray.t_min = 5.0;  // t > t_min only
  EXPECT_FALSE(kernel_hit(ray, tri).found());
  const auto void_ray = [&](auto change) {
    RayD r;
    change(r);
    return kernel_hit(r, tri).found();
  };
  EXPECT_FALSE(void_ray([](RayD& r) { r.origin.x = std::nan(""); }));
  EXPECT_FALSE(void_ray([](RayD& r) { r.direction.z = std::numeric_limits<double>::infinity(); }));
  EXPECT_FALSE(void_ray([](RayD& r) { r.direction = {}; }));
  EXPECT_FALSE(void_ray([](RayD& r) { r.t_min = 2.0; r.t_max = 1.0; }));
  EXPECT_FALSE(void_ray([](RayD& r) { r.direction.x = 1e-30; }));  // outside the double domain
  EXPECT_FALSE(void_ray([](RayD& r) { r.origin.x = 1e30; r.direction.x = -1e10; }));
  EXPECT_TRUE(void_ray([](RayD& r) { r.direction.x = 1e-19; }));   // inside it
  // A ray in the triangle's plane and a zero-area triangle are never hit.
  RayD in_plane;
  in_plane.origin = {-5, 0, 5};
  in_plane.direction = {1, 0, 0};
  EXPECT_FALSE(kernel_hit(in_plane, tri).found());
  const std::array<DVec3, 3> sliver{DVec3{-1, 0, 5}, DVec3{1, 0, 5}, DVec3{3, 0, 5}};
  RayD at_sliver;
  at_sliver.direction = {0, 0, 1};
  EXPECT_FALSE(kernel_hit(at_sliver, sliver).found());
}

TEST(DoubleScene, RejectsCoordinatesOutsideTheDomainAndBadIndices) {
  const auto make = [](DVec3 v, std::uint32_t index) {
    TriangleMeshD m;
    m.vertices = {DVec3{0, 0, 0}, DVec3{1, 0, 0}, v};
    m.triangles = {{0, 1, index}};
    DoubleScene scene(std::move(m));
  };
  using testing::contains;
  using testing::error_message;
  EXPECT_TRUE(contains(error_message([&] { make({0, std::nan(""), 0}, 2); }), "vertex 2 has coordinate y"));
  EXPECT_TRUE(contains(error_message([&] { make({1e30, 0, 0}, 2); }), "double domain"));
  EXPECT_TRUE(contains(error_message([&] { make({0, 0, 1e-30}, 2); }), "vertex 2 has coordinate z"));
  EXPECT_TRUE(contains(error_message([&] { make({0, 1, 0}, 3); }), "triangle 0 has index 3"));
  EXPECT_NO_THROW(make({0, 1e-19, 1e19}, 2));
}

TEST(DoubleScene, FloatBoxesContainTheirDoubleTriangles) {
  TriangleMeshD m;
  m.vertices = {DVec3{1e7 + 0.123456789, -2e7 + 1e-3, 3.3e7}, DVec3{1e7 + 0.5, -2e7, 3.3e7 + 0.1},
                DVec3{1e7, -2e7 - 0.7, 3.3e7 + 0.01}};
  m.triangles = {{0, 1, 2}};
  const DoubleScene scene(m);
  const AABB& box = scene.triangle_box(0);
  for (const DVec3& p : scene.triangle(0)) {
    for (int a = 0; a < 3; ++a) {
      EXPECT_LE(double(box.lo[a]), p[a]);
      EXPECT_GE(double(box.hi[a]), p[a]);
    }
  }
  // Outward rounding at 1e7 widens by at most one float ulp (1 or 2 units there).
  EXPECT_LE(double(box.hi.x) - double(box.lo.x), 0.5 + 2.0 * 1.0 + 1e-9);
}

}  // namespace
}  // namespace rayaccel
