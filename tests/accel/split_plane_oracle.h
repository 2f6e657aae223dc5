// Test cases for the split-plane structures (kd-tree, BSP tree), built on the grids' spatial_oracle.h: one list of
// adversarial scenes and rays (rays in and along split planes, +-0 directions, fins touching planes from one side,
// duplicates, huge coordinates) that both test files run against brute force, with validate().
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "rayaccel/accel/registry.h"
#include "rayaccel/scene/scene.h"
#include "spatial_oracle.h"

namespace rayaccel::spatial_test {

inline Scene random_soup(int count, std::uint32_t seed, float size = 0.1f) {
  return Scene::from_mesh(testing::random_soup(std::uint32_t(count), seed, size), "soup");
}

inline Scene closed_sphere(int rings, int segments) {
  return Scene::from_mesh(testing::closed_sphere(std::uint32_t(rings), std::uint32_t(segments)), "sphere");
}

/// Quads (two triangles each) on the integer planes x = 0..n-1 and z = 0..n-1, each spanning [0, n-1] in its other
/// two coordinates, plus fins touching those planes from one side: split planes land on the quads, and rays
/// moving within a plane hit fins exactly on their in-plane edges.
inline Scene quad_grid(int n) {
  TriangleMesh mesh;
  const float e = float(n - 1);
  auto quad = [&](Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
    const auto base = std::uint32_t(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), {a, b, c, d});
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.triangles.push_back({base, base + 2, base + 3});
  };
  auto triangle = [&](Vec3 a, Vec3 b, Vec3 c) {
    const auto base = std::uint32_t(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), {a, b, c});
    mesh.triangles.push_back({base, base + 1, base + 2});
  };
  for (int i = 0; i < n; ++i) {
    const float k = float(i);
    quad({k, 0, 0}, {k, e, 0}, {k, e, e}, {k, 0, e});
    quad({0, 0, k}, {e, 0, k}, {e, e, k}, {0, e, k});
    // Fins: triangles with one edge in the plane x = k (or z = k) that reach into one side only, so a ray moving
    // in the plane hits them on that edge and a traversal that drops either side misses some.
    for (int j = 0; j + 1 < n; ++j) {
      const float a = float(j) + 0.2f, b = float((i + j) % n) + 0.3f;
      const float side = (j % 2) ? 0.4f : -0.4f;
      triangle({k, a, b}, {k, a + 0.6f, b + 0.5f}, {k + side, a + 0.3f, b + 0.2f});
      triangle({b, a, k}, {b + 0.5f, a + 0.6f, k}, {b + 0.2f, a + 0.3f, k - side});
    }
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

/// Random rays around the box [lo, hi]^3 (see testing::random_rays: some with +-0 components or a finite t_max).
inline std::vector<Ray> random_rays(int count, std::uint32_t seed, float lo = -1.0f, float hi = 1.0f) {
  return testing::random_rays(std::uint32_t(count), seed, AABB(Vec3{lo}, Vec3{hi}));
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

/// Builds `spec` over `scene`, expects validate() to pass and every ray to agree with brute force.
inline void expect_matches_brute_force(const std::string& spec, const Scene& scene, const std::vector<Ray>& rays,
                                       const std::string& label) {
  std::unique_ptr<Accelerator> accel = make_accelerator(spec);
  accel->build(scene);
  const std::vector<std::string> problems = accel->validate();
  EXPECT_TRUE(problems.empty()) << spec << " on " << label << ": " << (problems.empty() ? "" : problems.front());
  testing::expect_matches_brute_force(*accel, scene, rays, spec + " on " + label);
}

/// Runs the shared case list (soups, sphere, quad grid with in-plane rays, duplicates, spheres, one triangle, an
/// empty scene, huge coordinates) for one accelerator spec.
inline void run_oracle_cases(const std::string& spec) {
  expect_matches_brute_force(spec, random_soup(300, 1), random_rays(400, 2), "random soup");
  expect_matches_brute_force(spec, random_soup(200, 3, 0.6f), random_rays(400, 4), "soup of large triangles");
  expect_matches_brute_force(spec, closed_sphere(12, 16), random_rays(400, 5), "closed sphere");
  expect_matches_brute_force(spec, quad_grid(6), plane_rays(6, 6), "quad grid, in-plane rays");
  const auto unit = [](int, int k) { return float(k); };
  const auto uneven = [](int axis, int k) { return 0.37f * float(k * k) - 1.3f + 0.1f * float(axis); };
  expect_matches_brute_force(spec, Scene::from_mesh(testing::checkerboard_faces(4, unit)),
                             testing::rays_along_planes(4, unit), "checkerboard, rays along planes");
  expect_matches_brute_force(spec, Scene::from_mesh(testing::checkerboard_faces(4, uneven)),
                             testing::rays_along_planes(4, uneven), "uneven checkerboard, rays along planes");
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
