// Test scenes, the brute-force comparison and the validate() check shared by the grid, two-level grid and octree
// tests: random soups, a closed sphere, axis-aligned quad stacks, rays with +-0 components and rays along planes.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/brute_force.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel::testing {

/// Adds a test failure when validate() reports a problem, naming the count and the first.
inline void expect_valid(const Accelerator& a) {
  const auto problems = a.validate();
  EXPECT_TRUE(problems.empty()) << problems.size() << " problems, first: " << (problems.empty() ? "" : problems.front());
}

inline TriangleMesh random_soup(std::uint32_t count, std::uint32_t seed, float size = 0.1f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-1.0f, 1.0f), off(-size, size);
  TriangleMesh m;
  for (std::uint32_t i = 0; i < count; ++i) {
    const Vec3 c{pos(rng), pos(rng), pos(rng)};
    for (int k = 0; k < 3; ++k) m.vertices.push_back(c + Vec3{off(rng), off(rng), off(rng)});
    m.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  return m;
}

/// A closed UV sphere of radius 1 around the origin (shared vertices, so it is watertight).
inline TriangleMesh closed_sphere(std::uint32_t rings, std::uint32_t segments) {
  TriangleMesh m;
  m.vertices.push_back({0, 1, 0});
  for (std::uint32_t r = 1; r < rings; ++r) {
    const float theta = 3.14159265f * float(r) / float(rings);
    for (std::uint32_t s = 0; s < segments; ++s) {
      const float phi = 2.0f * 3.14159265f * float(s) / float(segments);
      m.vertices.push_back({std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)});
    }
  }
  m.vertices.push_back({0, -1, 0});
  const auto ring = [&](std::uint32_t r, std::uint32_t s) { return 1 + (r - 1) * segments + s % segments; };
  const std::uint32_t south = std::uint32_t(m.vertices.size() - 1);
  for (std::uint32_t s = 0; s < segments; ++s) {
    m.triangles.push_back({0, ring(1, s + 1), ring(1, s)});
    m.triangles.push_back({south, ring(rings - 1, s), ring(rings - 1, s + 1)});
    for (std::uint32_t r = 1; r + 1 < rings; ++r) {
      m.triangles.push_back({ring(r, s), ring(r, s + 1), ring(r + 1, s)});
      m.triangles.push_back({ring(r, s + 1), ring(r + 1, s + 1), ring(r + 1, s)});
    }
  }
  return m;
}

/// Unit quads (two triangles each) on the integer lattice of [0, n]^3: for every axis a and integer plane, the
/// quads of that plane, so every cell face of the lattice is covered.
inline TriangleMesh quad_lattice(int n) {
  TriangleMesh m;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int k = 0; k <= n; ++k) {
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          const auto base = std::uint32_t(m.vertices.size());
          for (int corner = 0; corner < 4; ++corner) {
            Vec3 p;
            p[axis] = float(k);
            p[u] = float(i + (corner & 1));
            p[v] = float(j + (corner >> 1));
            m.vertices.push_back(p);
          }
          m.triangles.push_back({base, base + 1, base + 3});
          m.triangles.push_back({base, base + 3, base + 2});
        }
      }
    }
  }
  return m;
}

/// Checkerboard faces on given planes: for every axis a and inner plane k (1..n-1), a quad in plane(a, k) over every
/// other cell (i, j) of the two other axes. A ray running in a plane between a covered and an empty cell hits the
/// quad's free edge, which only a structure that references the quad on both sides of the plane finds reliably.
/// Two tiny corner triangles pin the scene bounds to [plane(.., 0), plane(.., n)].
template <class Plane>
TriangleMesh checkerboard_faces(int n, const Plane& plane) {
  TriangleMesh m;
  const auto add = [&](Vec3 a, Vec3 b, Vec3 c) {
    const auto base = std::uint32_t(m.vertices.size());
    m.vertices.insert(m.vertices.end(), {a, b, c});
    m.triangles.push_back({base, base + 1, base + 2});
  };
  const Vec3 lo{plane(0, 0), plane(1, 0), plane(2, 0)}, hi{plane(0, n), plane(1, n), plane(2, n)};
  add(lo, lo + Vec3{1e-3f, 0, 0}, lo + Vec3{0, 1e-3f, 0});
  add(hi, hi - Vec3{1e-3f, 0, 0}, hi - Vec3{0, 1e-3f, 0});
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int k = 1; k < n; ++k) {
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          if ((i + j + k) % 2) continue;
          Vec3 p[4];
          for (int corner = 0; corner < 4; ++corner) {
            p[corner][axis] = plane(axis, k);
            p[corner][u] = plane(u, i + (corner & 1));
            p[corner][v] = plane(v, j + (corner >> 1));
          }
          add(p[0], p[1], p[3]);
          add(p[0], p[3], p[2]);
        }
      }
    }
  }
  return m;
}

/// Rays in every inner plane `plane(axis, k)`, heading along each other axis, through all points (plane(u, i),
/// plane(v, j) / 2-offsets) of the lattice: they run along cell boundaries and through quad edges.
template <class Plane>
std::vector<Ray> rays_along_planes(int n, const Plane& plane) {
  std::vector<Ray> rays;
  for (int axis = 0; axis < 3; ++axis) {
    for (int along = 0; along < 3; ++along) {
      if (along == axis) continue;
      const int other = 3 - axis - along;
      for (int k = 0; k <= n; ++k) {
        for (int i = 0; i <= 2 * n; ++i) {
          for (int sign = 0; sign < 2; ++sign) {
            Ray r;
            r.origin[axis] = plane(axis, k);
            r.origin[other] = i % 2 ? 0.5f * (plane(other, i / 2) + plane(other, i / 2 + 1)) : plane(other, i / 2);
            r.origin[along] = sign ? plane(along, n) + 1.0f : plane(along, 0) - 1.0f;
            r.direction = Vec3{};
            r.direction[along] = sign ? -1.0f : 1.0f;
            if (i % 4 == 1) r.direction[axis] = -0.0f;
            rays.push_back(r);
          }
        }
      }
    }
  }
  return rays;
}

/// Random rays from a box around the scene toward it; one in four has one or two direction components set to +0
/// or -0, one in eight has a finite t_max.
inline std::vector<Ray> random_rays(std::uint32_t count, std::uint32_t seed, const AABB& target, float spread = 2.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const Vec3 c = target.center(), e = target.extent() * 0.5f * spread + Vec3{1e-3f};
  std::vector<Ray> rays;
  for (std::uint32_t i = 0; i < count; ++i) {
    Ray r;
    r.origin = c + Vec3{(2 * unit(rng) - 1) * e.x, (2 * unit(rng) - 1) * e.y, (2 * unit(rng) - 1) * e.z};
    const Vec3 aim = c + Vec3{(2 * unit(rng) - 1) * e.x, (2 * unit(rng) - 1) * e.y, (2 * unit(rng) - 1) * e.z} * 0.5f;
    r.direction = aim - r.origin;
    if (i % 4 == 1) r.direction[i % 3] = (i & 8) ? -0.0f : 0.0f;
    if (i % 4 == 3) {
      r.direction[i % 3] = (i & 8) ? -0.0f : 0.0f;
      r.direction[(i + 1) % 3] = (i & 16) ? -0.0f : 0.0f;
    }
    if (i % 8 == 5) r.t_max = unit(rng);
    rays.push_back(r);
  }
  return rays;
}

/// Compares closest hits and occlusion of `accel` with brute force over `scene` for every ray. A different
/// primitive is accepted only when both report (nearly) the same t.
inline void expect_matches_brute_force(const Accelerator& accel, const Scene& scene, const std::vector<Ray>& rays,
                                       const std::string& label) {
  BruteForce oracle;
  oracle.build(scene);
  int failures = 0;
  for (std::size_t i = 0; i < rays.size() && failures < 10; ++i) {
    const Hit want = oracle.intersect(rays[i]);
    const Hit got = accel.intersect(rays[i]);
    const bool occluded = accel.occluded(rays[i]);
    bool ok = want.found() == got.found() && occluded == want.found();
    if (ok && want.found()) {
      const float tol = 1e-6f * std::max(1.0f, std::fabs(want.t));
      ok = std::fabs(want.t - got.t) <= tol && (want.prim_id == got.prim_id || want.t == got.t);
    }
    if (!ok) {
      ++failures;
      ADD_FAILURE() << label << ": ray " << i << " o=(" << rays[i].origin.x << "," << rays[i].origin.y << ","
                    << rays[i].origin.z << ") d=(" << rays[i].direction.x << "," << rays[i].direction.y << ","
                    << rays[i].direction.z << ") tmax=" << rays[i].t_max << ": brute force t=" << want.t
                    << " prim=" << want.prim_id << ", got t=" << got.t << " prim=" << got.prim_id
                    << " occluded=" << occluded;
    }
  }
}

/// Rays lying exactly in the plane coordinate[axis] = value, heading along `along` (+ or -), through a lattice of
/// points of `box`: they run along cell boundaries when `value` is a cell plane.
inline std::vector<Ray> rays_in_plane(int axis, float value, int along, const AABB& box, int per_side) {
  std::vector<Ray> rays;
  const int other = 3 - axis - along;
  for (int sign = 0; sign < 2; ++sign) {
    for (int i = 0; i <= per_side; ++i) {
      Ray r;
      r.origin[axis] = value;
      r.origin[other] = box.lo[other] + (box.hi[other] - box.lo[other]) * float(i) / float(per_side);
      r.origin[along] = sign ? box.hi[along] + 1.0f : box.lo[along] - 1.0f;
      r.direction = Vec3{};
      r.direction[along] = sign ? -1.0f : 1.0f;
      if (i % 2) r.direction[axis] = -0.0f;
      rays.push_back(r);
    }
  }
  return rays;
}

}  // namespace rayaccel::testing
