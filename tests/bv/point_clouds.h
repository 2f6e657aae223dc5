// Point clouds and ray generators shared by the bounding-volume tests: random, flat, collinear, single, duplicate,
// huge-coordinate and sliver sets.
#pragma once

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "rayaccel/core/vec3.h"

namespace rayaccel::test {

struct PointCloud {
  std::string name;
  std::vector<Vec3> points;
};

inline Vec3 random_in_box(std::mt19937& rng, const Vec3& lo, const Vec3& hi) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  return {lo.x + u(rng) * (hi.x - lo.x), lo.y + u(rng) * (hi.y - lo.y), lo.z + u(rng) * (hi.z - lo.z)};
}

/// Rotates p by the rotation taking the z axis to (normalized) n, about the origin, then adds offset.
inline Vec3 rotate_and_shift(const Vec3& p, const Vec3& n_raw, const Vec3& offset) {
  const Vec3 n = normalize(n_raw);
  const Vec3 helper = std::fabs(n.x) < 0.5f ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 u = normalize(cross(helper, n));
  const Vec3 v = cross(n, u);
  return u * p.x + v * p.y + n * p.z + offset;
}

/// The standard clouds every volume is tested on.
inline std::vector<PointCloud> standard_clouds(unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<PointCloud> clouds;
  const auto random_cloud = [&](const std::string& name, int n, const Vec3& lo, const Vec3& hi) {
    PointCloud c{name, {}};
    for (int i = 0; i < n; ++i) c.points.push_back(random_in_box(rng, lo, hi));
    clouds.push_back(std::move(c));
  };
  random_cloud("random3", 3, {-1, -1, -1}, {1, 1, 1});
  random_cloud("random12", 12, {-1, -2, 0}, {3, 1, 0.5f});
  random_cloud("random300", 300, {-5, -5, -5}, {5, 5, 5});
  random_cloud("offset", 60, {1000, 2000, -3000}, {1000.5f, 2001, -2999.8f});
  random_cloud("flat_z", 40, {-1, -1, 0.25f}, {1, 1, 0.25f});
  random_cloud("huge", 50, {-1e15f, -1e15f, -1e15f}, {1e15f, 1e15f, 1e15f});
  random_cloud("huge_offset", 50, {1e15f, 1e15f, 1e15f}, {1.01e15f, 1.02e15f, 1.005e15f});
  random_cloud("tiny", 30, {-1e-30f, -1e-30f, -1e-30f}, {1e-30f, 1e-30f, 1e-30f});
  {
    PointCloud c{"flat_rotated", {}};
    for (int i = 0; i < 40; ++i) {
      const Vec3 p = random_in_box(rng, {-2, -1, 0}, {2, 1, 0});
      c.points.push_back(rotate_and_shift(p, {1, 2, 3}, {0.5f, -1, 2}));
    }
    clouds.push_back(std::move(c));
  }
  {
    PointCloud c{"sliver", {}};
    for (int i = 0; i < 80; ++i) {
      const Vec3 p = random_in_box(rng, {-5, -0.05f, -0.02f}, {5, 0.05f, 0.02f});
      c.points.push_back(rotate_and_shift(p, {0.3f, -0.8f, 0.5f}, {1, 2, 3}));
    }
    clouds.push_back(std::move(c));
  }
  {
    PointCloud c{"collinear", {}};
    for (int i = 0; i < 20; ++i) {
      const float t = std::uniform_real_distribution<float>(-3, 3)(rng);
      c.points.push_back(Vec3{1, 2, 3} + Vec3{0.3f, -0.7f, 0.2f} * t);
    }
    clouds.push_back(std::move(c));
  }
  clouds.push_back({"single", {{0.1f, -7.0f, 3.5f}}});
  clouds.push_back({"duplicates", {{1, 1, 1}, {1, 1, 1}, {2, 0, 1}, {2, 0, 1}, {1, 1, 1}, {0, 3, 2}, {0, 3, 2}}});
  {
    PointCloud c{"many_duplicates", {}};
    for (int i = 0; i < 100; ++i) c.points.push_back(i % 3 == 0 ? Vec3{0, 0, 0} : (i % 3 == 1 ? Vec3{1, 0, 0} : Vec3{0, 1, 1}));
    clouds.push_back(std::move(c));
  }
  return clouds;
}

}  // namespace rayaccel::test
