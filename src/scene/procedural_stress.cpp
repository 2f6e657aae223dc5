// Generators for stress scenes: a closed torus-knot tube and a sparse stadium (teapot in a stadium, Haines 1988),
// long thin slivers, random triangle soup, and a watertight subdivided icosahedron.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <unordered_map>
#include <utility>

#include "procedural.h"

namespace rayaccel::procedural {

TriangleMesh torus_knot(int p, int q, int segments, int tube_segments, float tube_radius, float scale) {
  TriangleMesh mesh;
  mesh.vertices.reserve(static_cast<std::size_t>(segments) * tube_segments);
  for (int i = 0; i < segments; ++i) {
    const double phi = 2.0 * std::numbers::pi * i / segments;
    const double r = 2.0 + std::cos(q * phi), dr = -q * std::sin(q * phi);
    const double cp = std::cos(p * phi), sp = std::sin(p * phi);
    const Vec3 point{static_cast<float>(r * cp), static_cast<float>(r * sp), static_cast<float>(-std::sin(q * phi))};
    const Vec3 tangent = normalize(Vec3{static_cast<float>(dr * cp - p * r * sp),
                                        static_cast<float>(dr * sp + p * r * cp),
                                        static_cast<float>(-q * std::cos(q * phi))});
    // The tangent always has a component p*r round the Z axis and the point none, so they are never parallel.
    const Vec3 binormal = normalize(cross(tangent, point));
    const Vec3 normal = cross(binormal, tangent);
    for (int j = 0; j < tube_segments; ++j) {
      const double theta = 2.0 * std::numbers::pi * j / tube_segments;
      const Vec3 offset = normal * static_cast<float>(std::cos(theta)) + binormal * static_cast<float>(std::sin(theta));
      const Vec3 v = (point + offset * tube_radius) * scale;
      mesh.vertices.push_back({v.x, -v.z, v.y});  // a rotation about X lays the knot in the XZ plane
    }
  }
  auto index = [&](int i, int j) {
    return static_cast<std::uint32_t>((i % segments) * tube_segments + (j % tube_segments));
  };
  mesh.triangles.reserve(2 * mesh.vertices.size());
  for (int i = 0; i < segments; ++i) {
    for (int j = 0; j < tube_segments; ++j) {
      // (normal, binormal, tangent) is right-handed, so stepping in theta before phi winds outward.
      mesh.triangles.push_back({index(i, j), index(i, j + 1), index(i + 1, j)});
      mesh.triangles.push_back({index(i + 1, j), index(i, j + 1), index(i + 1, j + 1)});
    }
  }
  return mesh;
}

namespace {

/// Appends the planar quad a-b-c-d (in cyclic order) as two triangles whose normal points along `facing`.
void add_quad(TriangleMesh& mesh, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& facing) {
  const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), {a, b, c, d});
  if (dot(cross(b - a, c - a), facing) >= 0.0f) {
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.triangles.push_back({base, base + 2, base + 3});
  } else {
    mesh.triangles.push_back({base, base + 2, base + 1});
    mesh.triangles.push_back({base, base + 3, base + 2});
  }
}

}  // namespace

TriangleMesh stadium(float size, int sectors, int tiers) {
  TriangleMesh mesh;
  const Vec3 up{0.0f, 1.0f, 0.0f};
  constexpr int kFieldCells = 4;
  const float half = 0.5f * size, cell = size / kFieldCells;
  for (int j = 0; j < kFieldCells; ++j) {
    for (int i = 0; i < kFieldCells; ++i) {
      const float x0 = -half + i * cell, z0 = -half + j * cell;
      add_quad(mesh, {x0, 0.0f, z0}, {x0 + cell, 0.0f, z0}, {x0 + cell, 0.0f, z0 + cell}, {x0, 0.0f, z0 + cell}, up);
    }
  }
  const float inner = 0.30f * size, outer = 0.48f * size;
  const float step_depth = (outer - inner) / tiers, step_height = 0.02f * size;
  for (int k = 0; k < sectors; ++k) {
    const double a0 = 2.0 * std::numbers::pi * k / sectors, a1 = 2.0 * std::numbers::pi * (k + 1) / sectors;
    auto at = [&](double angle, float radius, float y) {
      return Vec3{radius * static_cast<float>(std::cos(angle)), y, radius * static_cast<float>(std::sin(angle))};
    };
    const double mid = 0.5 * (a0 + a1);
    const Vec3 inward{-static_cast<float>(std::cos(mid)), 0.0f, -static_cast<float>(std::sin(mid))};
    for (int t = 0; t < tiers; ++t) {
      const float r0 = inner + t * step_depth, r1 = r0 + step_depth;
      const float y0 = t * step_height, y1 = y0 + step_height;
      add_quad(mesh, at(a0, r0, y0), at(a1, r0, y0), at(a1, r0, y1), at(a0, r0, y1), inward);  // riser
      add_quad(mesh, at(a0, r0, y1), at(a1, r0, y1), at(a1, r1, y1), at(a0, r1, y1), up);      // tread
    }
  }
  return mesh;
}

TriangleMesh slivers(int count, float half_length, float aspect, std::uint64_t seed) {
  Rng rng(seed);
  TriangleMesh mesh;
  mesh.vertices.reserve(3 * static_cast<std::size_t>(count));
  mesh.triangles.reserve(static_cast<std::size_t>(count));
  const float width = 2.0f * half_length / aspect;
  for (int k = 0; k < count; ++k) {
    const Vec3 center = rng.in_cube();
    const Vec3 dir = rng.unit_vector();
    Vec3 side;
    do {
      side = cross(dir, rng.unit_vector());
    } while (length(side) < 1e-3f);
    side = normalize(side);
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(),
                         {center - dir * half_length, center + dir * half_length, center + side * width});
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return mesh;
}

TriangleMesh soup(int count, float size, std::uint64_t seed) {
  Rng rng(seed);
  TriangleMesh mesh;
  mesh.vertices.reserve(3 * static_cast<std::size_t>(count));
  mesh.triangles.reserve(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    const Vec3 center = rng.in_cube();
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    for (int v = 0; v < 3; ++v) mesh.vertices.push_back(center + rng.in_cube() * size);
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return mesh;
}

TriangleMesh icosphere(int level, float radius) {
  using Point = std::array<double, 3>;
  const double phi = 0.5 * (1.0 + std::sqrt(5.0));
  std::vector<Point> points;
  for (double s : {-1.0, 1.0}) {
    for (double t : {-phi, phi}) {
      points.push_back({s, t, 0.0});
      points.push_back({0.0, s, t});
      points.push_back({t, 0.0, s});
    }
  }
  auto dist2 = [&](std::uint32_t a, std::uint32_t b) {
    double d = 0.0;
    for (int k = 0; k < 3; ++k) d += (points[a][k] - points[b][k]) * (points[a][k] - points[b][k]);
    return d;
  };
  auto is_edge = [&](std::uint32_t a, std::uint32_t b) { return std::fabs(dist2(a, b) - 4.0) < 1e-9; };
  // The 20 faces: the vertex triples at mutual edge distance 2, wound outward.
  std::vector<std::array<std::uint32_t, 3>> faces;
  for (std::uint32_t a = 0; a < 12; ++a) {
    for (std::uint32_t b = a + 1; b < 12; ++b) {
      for (std::uint32_t c = b + 1; c < 12; ++c) {
        if (!(is_edge(a, b) && is_edge(b, c) && is_edge(a, c))) continue;
        const Point& pa = points[a];
        const Point& pb = points[b];
        const Point& pc = points[c];
        const double e1[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
        const double e2[3] = {pc[0] - pa[0], pc[1] - pa[1], pc[2] - pa[2]};
        const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0]};
        const bool outward = n[0] * (pa[0] + pb[0] + pc[0]) + n[1] * (pa[1] + pb[1] + pc[1]) +
                                 n[2] * (pa[2] + pb[2] + pc[2]) > 0.0;
        faces.push_back(outward ? std::array<std::uint32_t, 3>{a, b, c} : std::array<std::uint32_t, 3>{a, c, b});
      }
    }
  }
  auto project = [](Point p) {
    const double len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    return Point{p[0] / len, p[1] / len, p[2] / len};
  };
  for (Point& p : points) p = project(p);
  for (int l = 0; l < level; ++l) {
    std::unordered_map<std::uint64_t, std::uint32_t> midpoints;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
      const auto [it, inserted] = midpoints.try_emplace(key, static_cast<std::uint32_t>(points.size()));
      if (inserted) {
        points.push_back(project({points[a][0] + points[b][0], points[a][1] + points[b][1],
                                  points[a][2] + points[b][2]}));
      }
      return it->second;
    };
    std::vector<std::array<std::uint32_t, 3>> finer;
    finer.reserve(4 * faces.size());
    for (const auto& f : faces) {
      const std::uint32_t ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({ab, f[1], bc});
      finer.push_back({ca, bc, f[2]});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }
  TriangleMesh mesh;
  mesh.vertices.reserve(points.size());
  for (const Point& p : points) {
    mesh.vertices.push_back({static_cast<float>(p[0] * radius), static_cast<float>(p[1] * radius),
                             static_cast<float>(p[2] * radius)});
  }
  mesh.triangles = std::move(faces);
  return mesh;
}

}  // namespace rayaccel::procedural
