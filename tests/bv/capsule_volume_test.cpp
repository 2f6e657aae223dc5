// Capsules: points on a known capsule and on a sphere are fitted about as tightly as their closed forms, and the
// ray test agrees with the distance from the ray to the axis segment (a convex function of t, minimized by ternary
// search in double) away from the surface.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "point_clouds.h"
#include "rayaccel/bv/capsule_volume.h"
#include "rayaccel/bv/tightness.h"

namespace rayaccel {
namespace {

constexpr double kPi = std::numbers::pi;

/// Points on the surface of the capsule of radius r around [(0,0,0), (length,0,0)], rotated and shifted, with the
/// two tips and the rim circles included.
std::vector<Vec3> capsule_surface(float length, float r, int count) {
  std::mt19937 rng(9);
  std::normal_distribution<float> gauss;
  std::vector<Vec3> pts;
  for (int i = 0; i < count; ++i) {
    Vec3 u{gauss(rng), gauss(rng), gauss(rng)};
    u = normalize(u) * r;
    if (i == 0) u = {-r, 0, 0};
    if (i == 1) u = {r, 0, 0};
    const float x = u.x < 0 ? u.x : (i % 3 == 0 ? u.x + length : std::uniform_real_distribution<float>(0, length)(rng));
    const Vec3 p = u.x < 0 || i % 3 == 0 ? Vec3{x, u.y, u.z} : Vec3{x, normalize(Vec3{0, u.y, u.z}).y * r,
                                                                    normalize(Vec3{0, u.y, u.z}).z * r};
    pts.push_back(test::rotate_and_shift(p, {2, -1, 0.5f}, {3, 1, -2}));
  }
  return pts;
}

TEST(BvCapsule, KnownCapsuleIsFittedClosely) {
  const std::vector<Vec3> pts = capsule_surface(4.0f, 1.0f, 4000);
  const CapsuleVolume v = CapsuleVolume::fit(pts);
  const double exact = 2.0 * kPi * 1.0 * 4.0 + 4.0 * kPi;  // side plus both hemispheres
  EXPECT_LE(v.surface_area(), exact * 1.05);
  EXPECT_GE(v.surface_area(), convex_hull_measure(pts).area * (1.0 - 1e-5));
  EXPECT_NEAR(v.segment_length(), 4.0, 0.4);
}

TEST(BvCapsule, SpherePointsGiveAShortCapsule) {
  std::mt19937 rng(2);
  std::normal_distribution<float> gauss;
  std::vector<Vec3> pts;
  for (int i = 0; i < 2000; ++i) pts.push_back(normalize(Vec3{gauss(rng), gauss(rng), gauss(rng)}) * 2.0f);
  const CapsuleVolume v = CapsuleVolume::fit(pts);
  EXPECT_LE(v.surface_area(), 4.0 * kPi * 4.0 * 1.1);
}

/// Distance from p to the segment [a, b], in double.
double segment_distance(const double p[3], const Vec3& a, const Vec3& b) {
  double ab[3], ap[3], ab2 = 0.0, t = 0.0;
  for (int k = 0; k < 3; ++k) {
    ab[k] = double(b[k]) - a[k];
    ap[k] = p[k] - a[k];
    ab2 += ab[k] * ab[k];
    t += ap[k] * ab[k];
  }
  t = ab2 > 0.0 ? std::clamp(t / ab2, 0.0, 1.0) : 0.0;
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) d2 += (ap[k] - t * ab[k]) * (ap[k] - t * ab[k]);
  return std::sqrt(d2);
}

TEST(BvCapsule, RayTestAgreesWithTheDistanceToTheAxis) {
  const std::vector<Vec3> pts = capsule_surface(3.0f, 0.5f, 500);
  const CapsuleVolume v = CapsuleVolume::fit(pts);
  const AABB b = v.bounds();
  const Vec3 size = b.hi - b.lo;
  std::mt19937 rng(23);
  int hits = 0, misses = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 from = test::random_in_box(rng, b.lo - size, b.hi + size);
    const Vec3 to = test::random_in_box(rng, b.lo, b.hi);
    const Ray ray{from, (i % 4 == 0) ? 0.6f : 0.0f, to - from, (i % 5 == 0) ? 0.8f : 3.0f};
    const PreparedRay prepared(ray);
    float entry;
    const bool got = v.intersect(CapsuleVolume::prepare(prepared), ray.t_min, ray.t_max, &entry);
    const auto distance = [&](double t) {
      const double p[3] = {ray.origin.x + t * ray.direction.x, ray.origin.y + t * ray.direction.y,
                           ray.origin.z + t * ray.direction.z};
      return segment_distance(p, v.a, v.b);
    };
    double lo = ray.t_min, hi = ray.t_max;
    for (int k = 0; k < 200; ++k) {
      const double m1 = lo + (hi - lo) / 3.0, m2 = hi - (hi - lo) / 3.0;
      (distance(m1) < distance(m2) ? hi : lo) = distance(m1) < distance(m2) ? m2 : m1;
    }
    const double t_closest = 0.5 * (lo + hi);
    const double closest = distance(t_closest);
    if (closest < v.radius * (1.0 - 1e-4)) {
      ASSERT_TRUE(got) << "ray " << i;
      // The reference entry: the first t of the segment within the radius (distance falls until t_closest).
      double enter_lo = ray.t_min, enter_hi = t_closest;
      if (distance(ray.t_min) > v.radius) {
        for (int k = 0; k < 200; ++k) {
          const double m = 0.5 * (enter_lo + enter_hi);
          (distance(m) > v.radius ? enter_lo : enter_hi) = m;
        }
      } else {
        enter_hi = ray.t_min;
      }
      EXPECT_LE(entry, enter_hi + 1e-5) << "ray " << i;
      ++hits;
    } else if (closest > v.radius * (1.0 + 1e-4)) {
      EXPECT_FALSE(got) << "ray " << i;
      ++misses;
    }
  }
  EXPECT_GT(hits, 500);
  EXPECT_GT(misses, 500);
}

}  // namespace
}  // namespace rayaccel
