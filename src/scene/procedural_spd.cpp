// Generators after Haines' Standard Procedural Databases (IEEE CG&A 1987): sphereflake, fractal mountain (midpoint
// displacement, Fournier, Fussell, Carpenter 1982) and Sierpinski tetrahedron.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <utility>

#include "procedural.h"

namespace rayaccel::procedural {

namespace {

/// Unit vectors u, v completing `axis` (unit) to a right-handed frame (u, v, axis).
void complete_frame(const Vec3& axis, Vec3& u, Vec3& v) {
  const Vec3 helper = std::fabs(axis.x) < 0.9f ? Vec3{1.0f, 0.0f, 0.0f} : Vec3{0.0f, 1.0f, 0.0f};
  u = normalize(cross(helper, axis));
  v = cross(axis, u);
}

void add_flake(std::vector<Sphere>& out, const Vec3& center, float radius, const Vec3& axis, int level) {
  out.push_back({center, radius});
  if (level == 0) return;
  // Child directions in the (u, v, axis) frame: 6 on the equator every 60 degrees, 3 at 50 degrees elevation
  // between them. Children touch their parent.
  Vec3 u, v;
  complete_frame(axis, u, v);
  const float child_radius = radius / 3.0f;
  for (int k = 0; k < 9; ++k) {
    const bool upper = k >= 6;
    const double azimuth = upper ? (2 * (k - 6) + 1) * std::numbers::pi / 3.0 : k * std::numbers::pi / 3.0;
    const double elevation = upper ? 50.0 * std::numbers::pi / 180.0 : 0.0;
    const auto cu = static_cast<float>(std::cos(elevation) * std::cos(azimuth));
    const auto cv = static_cast<float>(std::cos(elevation) * std::sin(azimuth));
    const auto ca = static_cast<float>(std::sin(elevation));
    const Vec3 dir = normalize(u * cu + v * cv + axis * ca);
    add_flake(out, center + dir * (radius + child_radius), child_radius, dir, level - 1);
  }
}

}  // namespace

std::vector<Sphere> sphereflake(int level, float radius) {
  std::vector<Sphere> spheres;
  std::size_t count = 0;
  for (int i = 0, p = 1; i <= level; ++i, p *= 9) count += static_cast<std::size_t>(p);
  spheres.reserve(count);
  add_flake(spheres, Vec3{}, radius, Vec3{0.0f, 1.0f, 0.0f}, level);
  return spheres;
}

TriangleMesh mountain(int level, float size, float height, float roughness, std::uint64_t seed) {
  const int n = 1 << level;
  const int side = n + 1;
  std::vector<double> h(static_cast<std::size_t>(side) * side, 0.0);
  auto at = [&](int i, int j) -> double& { return h[static_cast<std::size_t>(j) * side + i]; };
  Rng rng(seed);
  double amp = static_cast<double>(height) * size;
  for (int j : {0, n}) {
    for (int i : {0, n}) at(i, j) = rng.uniform(-amp, amp) * 0.5;
  }
  for (int step = n; step > 1; step /= 2) {
    const int half = step / 2;
    // Diamond step: square centres from their 4 corners.
    for (int j = half; j < n; j += step) {
      for (int i = half; i < n; i += step) {
        at(i, j) = 0.25 * (at(i - half, j - half) + at(i + half, j - half) + at(i - half, j + half) +
                           at(i + half, j + half)) +
                   rng.uniform(-amp, amp);
      }
    }
    // Square step: edge midpoints from their (up to 4) neighbours.
    for (int j = 0; j <= n; j += half) {
      for (int i = (j / half) % 2 == 0 ? half : 0; i <= n; i += step) {
        double sum = 0.0;
        int neighbours = 0;
        if (i >= half) { sum += at(i - half, j); ++neighbours; }
        if (i + half <= n) { sum += at(i + half, j); ++neighbours; }
        if (j >= half) { sum += at(i, j - half); ++neighbours; }
        if (j + half <= n) { sum += at(i, j + half); ++neighbours; }
        at(i, j) = sum / neighbours + rng.uniform(-amp, amp);
      }
    }
    amp *= roughness;
  }

  TriangleMesh mesh;
  mesh.vertices.reserve(h.size());
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const double x = -0.5 * size + static_cast<double>(size) * i / n;
      const double z = -0.5 * size + static_cast<double>(size) * j / n;
      mesh.vertices.push_back({static_cast<float>(x), static_cast<float>(at(i, j)), static_cast<float>(z)});
    }
  }
  mesh.triangles.reserve(2 * static_cast<std::size_t>(n) * n);
  auto index = [side](int i, int j) { return static_cast<std::uint32_t>(j * side + i); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      // Winding (i,j) -> (i,j+1) -> (i+1,j) gives a +Y normal on flat ground.
      mesh.triangles.push_back({index(i, j), index(i, j + 1), index(i + 1, j)});
      mesh.triangles.push_back({index(i + 1, j), index(i, j + 1), index(i + 1, j + 1)});
    }
  }
  return mesh;
}

float highest_point_near(const TriangleMesh& mountain, float x, float z, float radius) {
  float best = -std::numeric_limits<float>::infinity();
  for (const Vec3& p : mountain.vertices) {
    const float dx = p.x - x, dz = p.z - z;
    if (dx * dx + dz * dz <= radius * radius) best = std::max(best, p.y);
  }
  return best;
}

namespace {

using Tetra = std::array<std::array<double, 3>, 4>;

void add_tetra(TriangleMesh& mesh, const Tetra& t, const std::array<std::array<std::uint32_t, 3>, 4>& faces,
               int level) {
  if (level == 0) {
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    for (const auto& p : t) {
      mesh.vertices.push_back({static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])});
    }
    for (const auto& f : faces) mesh.triangles.push_back({base + f[0], base + f[1], base + f[2]});
    return;
  }
  // Corner copy c is the homothety of ratio 1/2 about vertex c: vertex k maps to (t[c] + t[k]) / 2, so the
  // face template (and its outward winding) carries over unchanged.
  for (int c = 0; c < 4; ++c) {
    Tetra child;
    for (int k = 0; k < 4; ++k) {
      for (int a = 0; a < 3; ++a) child[k][a] = 0.5 * (t[c][a] + t[k][a]);
    }
    add_tetra(mesh, child, faces, level - 1);
  }
}

}  // namespace

TriangleMesh sierpinski(int level, float edge) {
  const double a = edge;
  const double circumradius = a / std::sqrt(3.0);
  Tetra t;
  t[0] = {0.0, a * std::sqrt(2.0 / 3.0), 0.0};
  for (int k = 0; k < 3; ++k) {
    const double angle = std::numbers::pi / 2 + k * 2 * std::numbers::pi / 3;
    t[k + 1] = {circumradius * std::cos(angle), 0.0, circumradius * std::sin(angle)};
  }
  // Face k leaves out vertex k; wind it so that its normal points away from vertex k.
  std::array<std::array<std::uint32_t, 3>, 4> faces;
  for (std::uint32_t k = 0; k < 4; ++k) {
    std::array<std::uint32_t, 3> f;
    for (std::uint32_t i = 0, n = 0; i < 4; ++i) {
      if (i != k) f[n++] = i;
    }
    auto vec = [&](std::uint32_t from, std::uint32_t to) {
      return Vec3{static_cast<float>(t[to][0] - t[from][0]), static_cast<float>(t[to][1] - t[from][1]),
                  static_cast<float>(t[to][2] - t[from][2])};
    };
    if (dot(cross(vec(f[0], f[1]), vec(f[0], f[2])), vec(f[0], k)) > 0.0f) std::swap(f[1], f[2]);
    faces[k] = f;
  }
  TriangleMesh mesh;
  const std::size_t leaves = std::size_t{1} << (2 * level);
  mesh.vertices.reserve(4 * leaves);
  mesh.triangles.reserve(4 * leaves);
  add_tetra(mesh, t, faces, level);
  return mesh;
}

}  // namespace rayaccel::procedural
