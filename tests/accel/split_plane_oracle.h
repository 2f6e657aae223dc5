// Test scenes and rays for the spatial subdivisions (kd-tree, BSP tree), and the brute-force comparison both test
// files run: adversarial cases for split planes (rays in and along planes, +-0 directions) next to random soups.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "rayaccel/accel/brute_force.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/core/scene.h"

namespace rayaccel::spatial_test {

inline Scene random_soup(int count, std::uint32_t seed, float size = 0.1f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-1.0f, 1.0f), off(-size, size);
  TriangleMesh mesh;
  for (int i = 0; i < count; ++i) {
    const Vec3 c{pos(rng), pos(rng), pos(rng)};
    for (int k = 0; k < 3; ++k) mesh.vertices.push_back(c + Vec3{off(rng), off(rng), off(rng)});
    const auto b = static_cast<std::uint32_t>(3 * i);
    mesh.triangles.push_back({b, b + 1, b + 2});
  }
  return Scene::from_mesh(std::move(mesh), "soup");
}

/// A closed UV sphere of radius 1 (shared vertices, so the watertight test leaves no gaps).
inline Scene closed_sphere(int rings, int segments) {
  TriangleMesh mesh;
  mesh.vertices.push_back({0, 1, 0});
  for (int r = 1; r < rings; ++r) {
    const double theta = std::numbers::pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * std::numbers::pi * s / segments;
      mesh.vertices.push_back({float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                               float(std::sin(theta) * std::sin(phi))});
    }
  }
  mesh.vertices.push_back({0, -1, 0});
  const auto ring = [&](int r, int s) { return std::uint32_t(1 + (r - 1) * segments + (s % segments)); };
  const auto bottom = std::uint32_t(mesh.vertices.size() - 1);
  for (int s = 0; s < segments; ++s) {
    mesh.triangles.push_back({0, ring(1, s + 1), ring(1, s)});
    for (int r = 1; r + 1 < rings; ++r) {
      mesh.triangles.push_back({ring(r, s), ring(r, s + 1), ring(r + 1, s)});
      mesh.triangles.push_back({ring(r, s + 1), ring(r + 1, s + 1), ring(r + 1, s)});
    }
    mesh.triangles.push_back({ring(rings - 1, s), ring(rings - 1, s + 1), bottom});
  }
  return Scene::from_mesh(std::move(mesh), "sphere");
}

/// Unit quads (two triangles each) on the integer planes x = 0..n-1 and z = 0..n-1, each spanning [0, n-1] in its
/// other two coordinates: every split plane a builder can pick lies on a quad, and rays along them are parallel.
inline Scene quad_grid(int n) {
  TriangleMesh mesh;
  const float e = float(n - 1);
  auto quad = [&](Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
    const auto base = std::uint32_t(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), {a, b, c, d});
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.triangles.push_back({base, base + 2, base + 3});
  };
  for (int i = 0; i < n; ++i) {
    const float k = float(i);
    quad({k, 0, 0}, {k, e, 0}, {k, e, e}, {k, 0, e});
    quad({0, 0, k}, {e, 0, k}, {e, e, k}, {0, e, k});
  }
  return Scene::from_mesh(std::move(mesh), "quad_grid");
}

/// A soup where every triangle appears three times, plus zero-area triangles (a point and a segment).
inline Scene duplicates_and_degenerates() {
  Scene soup = random_soup(40, 7);
  TriangleMesh mesh;
  for (int copy = 0; copy < 3; ++copy) {
    for (std::uint32_t t = 0; t < soup.primitive_count(); ++t) {
      const auto base = std::uint32_t(mesh.vertices.size());
      for (const Vec3& v : soup.triangle(t)) mesh.vertices.push_back(v);
      mesh.triangles.push_back({base, base + 1, base + 2});
    }
  }
  const auto base = std::uint32_t(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), {{0.2f, 0.2f, 0.2f}, {0.2f, 0.2f, 0.2f}, {0.5f, 0.5f, 0.5f}});
  mesh.triangles.push_back({base, base + 1, base + 1});
  mesh.triangles.push_back({base, base + 1, base + 2});
  return Scene::from_mesh(std::move(mesh), "duplicates");
}

inline Scene random_spheres(int count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-1.0f, 1.0f), radius(0.01f, 0.15f);
  std::vector<Sphere> spheres;
  for (int i = 0; i < count; ++i) spheres.push_back({{pos(rng), pos(rng), pos(rng)}, radius(rng)});
  return Scene::from_spheres(std::move(spheres));
}

/// Random rays from a box around [-1.5, 1.5]^3 toward random targets in [-1, 1]^3.
inline std::vector<Ray> random_rays(int count, std::uint32_t seed, float lo = -1.0f, float hi = 1.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> origin(lo - 0.5f, hi + 0.5f), target(lo, hi);
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    const Vec3 o{origin(rng), origin(rng), origin(rng)};
    const Vec3 t{target(rng), target(rng), target(rng)};
    rays.push_back({o, 0.0f, t - o, std::numeric_limits<float>::infinity()});
  }
  return rays;
}

/// Rays that lie in integer planes (x = k or z = k) of a quad_grid(n), travelling along them with +0 and -0
/// direction components, rays through grid lines, rays starting on quads, and rays with t_max = 0.
inline std::vector<Ray> plane_rays(int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> coord(-0.5f, float(n) - 0.5f), dir(-1.0f, 1.0f);
  std::uniform_int_distribution<int> cell(0, n - 1);
  std::vector<Ray> rays;
  const float inf = std::numeric_limits<float>::infinity();
  for (int i = 0; i < 300; ++i) {
    const float k = float(cell(rng));
    const float zero = (i & 1) ? 0.0f : -0.0f;
    // In the plane x = k, moving within it (direction x = +-0).
    rays.push_back({{k, coord(rng), coord(rng)}, 0.0f, {zero, dir(rng), dir(rng)}, inf});
    // In the plane z = k, moving within it.
    rays.push_back({{coord(rng), coord(rng), k}, 0.0f, {dir(rng), dir(rng), zero}, inf});
    // Starting on a plane x = k, leaving it.
    rays.push_back({{k, coord(rng), coord(rng)}, 0.0f, {dir(rng), dir(rng), dir(rng)}, inf});
    // Along a grid line (x = k, z = j), direction only in y.
    rays.push_back({{k, coord(rng), float(cell(rng))}, 0.0f, {zero, (i & 2) ? 1.0f : -1.0f, zero}, inf});
    // Axis-parallel rays crossing the planes head on.
    rays.push_back({{-1.0f, coord(rng), coord(rng)}, 0.0f, {1.0f, zero, zero}, inf});
    rays.push_back({{coord(rng), coord(rng), float(n)}, 0.0f, {zero, zero, -1.0f}, inf});
    // t_max = 0 and a negative t_min.
    rays.push_back({{k, coord(rng), coord(rng)}, 0.0f, {1.0f, 0.0f, 0.0f}, 0.0f});
    rays.push_back({{k + 0.5f, coord(rng), coord(rng)}, -2.0f, {1.0f, zero, dir(rng)}, 3.0f});
  }
  return rays;
}

/// Checks `spec` against brute force on `scene` for closest hit and any hit; `label` names the case in failures.
inline void expect_matches_brute_force(const std::string& spec, const Scene& scene, const std::vector<Ray>& rays,
                                       const std::string& label) {
  BruteForce oracle;
  oracle.build(scene);
  std::unique_ptr<Accelerator> accel = make_accelerator(spec);
  accel->build(scene);
  const std::vector<std::string> problems = accel->validate();
  EXPECT_TRUE(problems.empty()) << spec << " on " << label << ": " << (problems.empty() ? "" : problems.front());
  int failures = 0;
  for (std::size_t i = 0; i < rays.size() && failures < 5; ++i) {
    const Ray& ray = rays[i];
    const Hit want = oracle.intersect(ray);
    const Hit got = accel->intersect(ray);
    const bool same_t = want.t == got.t || std::fabs(want.t - got.t) <= 1e-6f * std::fabs(want.t);
    const bool same_prim = want.prim_id == got.prim_id || (want.found() && got.found() && same_t);
    const bool same_occlusion = oracle.occluded(ray) == accel->occluded(ray);
    if (!same_t || !same_prim || !same_occlusion) {
      ++failures;
      ADD_FAILURE() << spec << " on " << label << ", ray " << i << " o=(" << ray.origin.x << "," << ray.origin.y
                    << "," << ray.origin.z << ") d=(" << ray.direction.x << "," << ray.direction.y << ","
                    << ray.direction.z << ") t=[" << ray.t_min << "," << ray.t_max << "]: want t=" << want.t
                    << " prim " << want.prim_id << ", got t=" << got.t << " prim " << got.prim_id
                    << (same_occlusion ? "" : " (occlusion differs)");
    }
  }
}

/// Runs the shared case list (soups, sphere, quad grid with in-plane rays, duplicates, spheres, one triangle, an
/// empty scene, huge coordinates) for one accelerator spec.
inline void run_oracle_cases(const std::string& spec) {
  expect_matches_brute_force(spec, random_soup(300, 1), random_rays(400, 2), "random soup");
  expect_matches_brute_force(spec, random_soup(200, 3, 0.6f), random_rays(400, 4), "soup of large triangles");
  expect_matches_brute_force(spec, closed_sphere(12, 16), random_rays(400, 5), "closed sphere");
  expect_matches_brute_force(spec, quad_grid(6), plane_rays(6, 6), "quad grid, in-plane rays");
  expect_matches_brute_force(spec, duplicates_and_degenerates(), random_rays(300, 8), "duplicates");
  expect_matches_brute_force(spec, random_spheres(100, 9), random_rays(300, 10), "spheres");
  TriangleMesh one;
  one.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  one.triangles = {{0, 1, 2}};
  expect_matches_brute_force(spec, Scene::from_mesh(one), random_rays(200, 11), "one triangle");
  expect_matches_brute_force(spec, Scene::from_mesh(TriangleMesh{}), random_rays(20, 12), "empty scene");
  const Scene small = closed_sphere(6, 8);
  TriangleMesh huge;
  for (const Vec3& v : small.mesh().vertices) huge.vertices.push_back(v * 1e15f);
  huge.triangles = small.mesh().triangles;
  expect_matches_brute_force(spec, Scene::from_mesh(huge), random_rays(200, 13, -1e15f, 1e15f), "huge coordinates");
}

}  // namespace rayaccel::spatial_test
