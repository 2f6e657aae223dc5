// Scenes, rays and the brute-force comparison shared by the BVH tests.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/brute_force.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel::bvh_test {

inline Scene random_soup(std::uint32_t count, std::uint32_t seed, float size = 0.1f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-1.0f, 1.0f), off(-size, size);
  TriangleMesh mesh;
  for (std::uint32_t i = 0; i < count; ++i) {
    const Vec3 c{pos(rng), pos(rng), pos(rng)};
    for (int k = 0; k < 3; ++k) mesh.vertices.push_back(c + Vec3{off(rng), off(rng), off(rng)});
    mesh.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  return Scene::from_mesh(std::move(mesh), "soup");
}

/// A closed UV sphere of radius 1 around the origin.
inline TriangleMesh sphere_mesh(std::uint32_t rings, std::uint32_t segments) {
  TriangleMesh mesh;
  const float pi = 3.14159265358979f;
  mesh.vertices.push_back({0, 1, 0});
  for (std::uint32_t r = 1; r < rings; ++r) {
    const float theta = pi * static_cast<float>(r) / static_cast<float>(rings);
    for (std::uint32_t s = 0; s < segments; ++s) {
      const float phi = 2 * pi * static_cast<float>(s) / static_cast<float>(segments);
      mesh.vertices.push_back({std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)});
    }
  }
  mesh.vertices.push_back({0, -1, 0});
  const auto bottom = static_cast<std::uint32_t>(mesh.vertices.size() - 1);
  auto ring = [&](std::uint32_t r, std::uint32_t s) { return 1 + (r - 1) * segments + s % segments; };
  for (std::uint32_t s = 0; s < segments; ++s) mesh.triangles.push_back({0, ring(1, s + 1), ring(1, s)});
  for (std::uint32_t r = 1; r + 1 < rings; ++r) {
    for (std::uint32_t s = 0; s < segments; ++s) {
      mesh.triangles.push_back({ring(r, s), ring(r, s + 1), ring(r + 1, s)});
      mesh.triangles.push_back({ring(r, s + 1), ring(r + 1, s + 1), ring(r + 1, s)});
    }
  }
  for (std::uint32_t s = 0; s < segments; ++s) mesh.triangles.push_back({bottom, ring(rings - 1, s), ring(rings - 1, s + 1)});
  return mesh;
}

/// A grid of n x n quads in the plane y = 0 (flat geometry), spanning [-1, 1]^2.
inline TriangleMesh grid_mesh(std::uint32_t n) {
  TriangleMesh mesh;
  for (std::uint32_t j = 0; j <= n; ++j) {
    for (std::uint32_t i = 0; i <= n; ++i) {
      mesh.vertices.push_back({-1.0f + 2.0f * static_cast<float>(i) / static_cast<float>(n), 0.0f,
                               -1.0f + 2.0f * static_cast<float>(j) / static_cast<float>(n)});
    }
  }
  for (std::uint32_t j = 0; j < n; ++j) {
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t a = j * (n + 1) + i;
      mesh.triangles.push_back({a, a + 1, a + n + 1});
      mesh.triangles.push_back({a + 1, a + n + 2, a + n + 1});
    }
  }
  return mesh;
}

/// Overlapping coplanar triangles in z = 0.5, plus copies of one triangle (duplicates) and zero-area ones.
inline Scene coplanar_and_duplicates(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-1.0f, 1.0f);
  TriangleMesh mesh;
  for (std::uint32_t i = 0; i < 200; ++i) {
    for (int k = 0; k < 3; ++k) mesh.vertices.push_back({pos(rng), pos(rng), 0.5f});
    mesh.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  mesh.vertices.push_back({-0.5f, -0.5f, -0.5f});
  mesh.vertices.push_back({0.5f, -0.5f, -0.5f});
  mesh.vertices.push_back({0.0f, 0.5f, -0.5f});
  mesh.vertices.push_back({0.2f, 0.2f, 0.2f});
  for (int i = 0; i < 40; ++i) mesh.triangles.push_back({base, base + 1, base + 2});      // duplicates
  for (int i = 0; i < 10; ++i) mesh.triangles.push_back({base + 3, base + 3, base + 3});  // points
  for (int i = 0; i < 10; ++i) mesh.triangles.push_back({base, base + 1, base + 1});      // segments
  return Scene::from_mesh(std::move(mesh), "coplanar");
}

inline Scene random_spheres(std::uint32_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-1.0f, 1.0f), rad(0.01f, 0.1f);
  std::vector<Sphere> spheres;
  for (std::uint32_t i = 0; i < count; ++i) spheres.push_back({{pos(rng), pos(rng), pos(rng)}, rad(rng)});
  return Scene::from_spheres(std::move(spheres));
}

/// Rays from around the scene's box toward points inside it, plus axis-parallel rays (with -0 components) and rays
/// with a limited t_max.
inline std::vector<Ray> random_rays(const AABB& box_in, std::uint32_t count, std::uint32_t seed) {
  AABB box = box_in.is_empty() ? AABB({-1, -1, -1}, {1, 1, 1}) : box_in;
  const Vec3 c = box.center();
  const Vec3 e = box.extent() * 0.5f + Vec3{1e-3f};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), unit(0.0f, 1.0f);
  std::vector<Ray> rays;
  for (std::uint32_t i = 0; i < count; ++i) {
    Ray r;
    r.origin = c + Vec3{u(rng), u(rng), u(rng)} * e * 2.0f;
    const Vec3 target = c + Vec3{u(rng), u(rng), u(rng)} * e;
    r.direction = target - r.origin;
    switch (i % 8) {
      case 5: r.direction = {0.0f, -0.0f, (i & 16) ? 1.0f : -1.0f}; break;
      case 6: r.direction = {-0.0f, (i & 16) ? 1.0f : -1.0f, 0.0f}; break;
      case 7: r.t_max = unit(rng) * 1.5f; break;
      default: break;
    }
    if (i % 13 == 0) r.t_min = 0.5f * unit(rng);
    rays.push_back(r);
  }
  return rays;
}

/// Expects the accelerator (already built over scene) to agree with brute force on every ray: closest t within
/// 1e-6 relative, the same primitive unless two are hit at that t, and the same any-hit answer.
/// Brute-force answers for rays over a scene; compute once and compare several structures against them.
struct OracleAnswers {
  std::vector<Hit> hits;
  std::vector<std::uint8_t> occluded;
};

inline OracleAnswers oracle_answers(const Scene& scene, const std::vector<Ray>& rays) {
  BruteForce oracle;
  oracle.build(scene);
  OracleAnswers out;
  out.hits.resize(rays.size());
  out.occluded.resize(rays.size());
  oracle.intersect(rays, out.hits);
  oracle.occluded(rays, out.occluded);
  return out;
}

inline void expect_agrees_with_brute_force(const Accelerator& accel, const Scene& scene,
                                           const std::vector<Ray>& rays, const OracleAnswers& oracle,
                                           const std::string& label) {
  int reported = 0;
  for (std::size_t i = 0; i < rays.size() && reported < 5; ++i) {
    const Hit want = oracle.hits[i];
    const Hit got = accel.intersect(rays[i]);
    bool ok = want.found() == got.found();
    if (ok && want.found()) {
      ok = std::fabs(got.t - want.t) <= 1e-6f * std::fabs(want.t);
      if (ok && got.prim_id != want.prim_id) {
        // Another primitive at the same distance is a tie, not an error: check it is really hit there.
        PreparedRay pr(rays[i]);
        Hit h = Hit::begin(pr);
        ok = scene.intersect(got.prim_id, pr, h) && std::fabs(h.t - want.t) <= 1e-6f * std::fabs(want.t);
      }
    }
    const bool want_occluded = oracle.occluded[i] != 0;
    ok = ok && accel.occluded(rays[i]) == want_occluded && want_occluded == want.found();
    if (!ok) {
      ++reported;
      ADD_FAILURE() << label << ": ray " << i << " got prim " << got.prim_id << " t " << got.t << ", brute force prim "
                    << want.prim_id << " t " << want.t;
    }
  }
}

}  // namespace rayaccel::bvh_test

namespace rayaccel::bvh_test {

inline void expect_agrees_with_brute_force(const Accelerator& accel, const Scene& scene,
                                           const std::vector<Ray>& rays, const std::string& label) {
  expect_agrees_with_brute_force(accel, scene, rays, oracle_answers(scene, rays), label);
}

}  // namespace rayaccel::bvh_test
