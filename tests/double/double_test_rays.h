// Scenes and rays of the double path's tests: a float model placed far from the origin in double, rays aimed exactly
// at its vertices, edge points and centres, random rays, and adversarial ones (axis-parallel, zero components, rays
// along edges, t ranges ending at a hit).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "rayaccel/core/ray_d.h"
#include "rayaccel/double/double_scene.h"

namespace rayaccel::testing {

/// Triangles of a double mesh as vertex triples (the exact reference's input).
inline std::vector<std::array<DVec3, 3>> triangles_of(const TriangleMeshD& mesh) {
  std::vector<std::array<DVec3, 3>> out;
  for (const auto& t : mesh.triangles) out.push_back({mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]});
  return out;
}

inline DVec3 centre_of(const TriangleMeshD& mesh) {
  DVec3 lo = mesh.vertices[0], hi = mesh.vertices[0];
  for (const DVec3& v : mesh.vertices) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], v[a]);
      hi[a] = std::max(hi[a], v[a]);
    }
  }
  return (lo + hi) * 0.5;
}

inline DVec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  for (;;) {
    const DVec3 v{n(rng), n(rng), n(rng)};
    const double len = length(v);
    if (len > 1e-3) return v * (1.0 / len);
  }
}

/// `count` rays from origins `distance` away from the mesh's centre, each aimed exactly at a vertex, at the double
/// midpoint of an edge, or at a triangle's centroid (in turn): direction = target - origin, t in (0, inf).
inline std::vector<RayD> aimed_rays(const TriangleMeshD& mesh, std::size_t count, double distance, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const DVec3 centre = centre_of(mesh);
  std::vector<RayD> rays;
  while (rays.size() < count) {
    const auto& tri = mesh.triangles[rng() % mesh.triangles.size()];
    const std::size_t k = rng() % 3;
    const DVec3 a = mesh.vertices[tri[k]], b = mesh.vertices[tri[(k + 1) % 3]], c = mesh.vertices[tri[(k + 2) % 3]];
    DVec3 target = a;
    if (rays.size() % 3 == 1) target = (a + b) * 0.5;
    if (rays.size() % 3 == 2) target = (a + b + c) * (1.0 / 3.0);
    RayD ray;
    ray.origin = centre + random_unit(rng) * distance;
    ray.direction = target - ray.origin;
    rays.push_back(ray);
  }
  return rays;
}

/// Random rays through the mesh's box, then adversarial ones: axis-parallel rays and rays with zero components
/// through vertices, rays along an edge (in the triangle's plane), t ranges that end exactly at an exact vertex
/// distance, and void rays.
inline std::vector<RayD> mixed_rays(const TriangleMeshD& mesh, std::size_t count, double size, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const DVec3 centre = centre_of(mesh);
  std::vector<RayD> rays;
  for (std::size_t i = 0; i < count; ++i) {
    RayD ray;
    ray.origin = centre + random_unit(rng) * (size * 2.0);
    const DVec3 target = centre + DVec3{unit(rng), unit(rng), unit(rng)} * (size * 0.5);
    ray.direction = target - ray.origin;
    rays.push_back(ray);
  }
  for (std::size_t i = 0; i < count / 4; ++i) {
    const auto& tri = mesh.triangles[rng() % mesh.triangles.size()];
    const DVec3 v = mesh.vertices[tri[0]], w = mesh.vertices[tri[1]];
    const int axis = static_cast<int>(rng() % 3);
    RayD axial;  // axis-parallel through a vertex: two zero direction components
    axial.direction = DVec3{};
    axial.direction[axis] = (i % 2 == 0) ? 1.0 : -1.0;
    axial.origin = v - axial.direction * (size * 3.0);
    rays.push_back(axial);
    RayD along;  // along an edge, from outside: in the triangle's plane
    along.origin = v - (w - v) * 2.0;
    along.direction = w - v;
    rays.push_back(along);
    RayD segment = axial;  // t_max exactly at the vertex's distance (size * 3 in units of a unit direction)
    segment.t_max = size * 3.0;
    rays.push_back(segment);
  }
  RayD nan_ray;
  nan_ray.origin = {std::nan(""), 0.0, 0.0};
  rays.push_back(nan_ray);
  RayD zero;
  zero.origin = centre;
  zero.direction = {};
  rays.push_back(zero);
  RayD inverted;
  inverted.origin = centre;
  inverted.t_min = 1.0;
  inverted.t_max = 0.5;
  rays.push_back(inverted);
  return rays;
}

}  // namespace rayaccel::testing
