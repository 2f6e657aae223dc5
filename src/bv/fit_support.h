// Private helpers shared by the bounding-volume fitters: a double-precision vector for fitting arithmetic, and the
// extremal points on the 13 k-DOP-26 directions that EPOS (spheres) and DiTO (OBBs) start from (Larsson 2008).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "rayaccel/core/vec3.h"
#include "rayaccel/geometry/ray_kdop.h"

namespace rayaccel::bv_detail {

/// A double-precision point, for fitting arithmetic.
struct Vec3d {
  double x = 0, y = 0, z = 0;
  Vec3d() = default;
  Vec3d(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  explicit Vec3d(const Vec3& p) : x(p.x), y(p.y), z(p.z) {}
  double operator[](int a) const { return a == 0 ? x : (a == 1 ? y : z); }
  double& operator[](int a) { return a == 0 ? x : (a == 1 ? y : z); }
};
inline Vec3d operator+(const Vec3d& a, const Vec3d& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3d operator-(const Vec3d& a, const Vec3d& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3d operator*(const Vec3d& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline double dot(const Vec3d& a, const Vec3d& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length_squared(const Vec3d& a) { return dot(a, a); }
inline double length(const Vec3d& a) { return std::sqrt(dot(a, a)); }
inline Vec3d normalize(const Vec3d& a) {
  const double len = length(a);
  return len > 0.0 ? a * (1.0 / len) : Vec3d{};
}
inline Vec3 to_float(const Vec3d& a) { return {float(a.x), float(a.y), float(a.z)}; }

/// Indices of the points with the smallest (entry 2j) and largest (entry 2j+1) projection on each of the 13
/// k-DOP-26 directions. Requires a non-empty span.
inline std::array<std::size_t, 26> extremal_points_26(std::span<const Vec3> points) {
  constexpr auto dirs = kdop_directions<26>();
  std::array<std::size_t, 26> arg{};
  std::array<double, 13> lo, hi;
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int j = 0; j < 13; ++j) {
      const double s = kdop_project(dirs[j], points[i]);
      if (s < lo[j]) { lo[j] = s; arg[2 * j] = i; }
      if (s > hi[j]) { hi[j] = s; arg[2 * j + 1] = i; }
    }
  }
  return arg;
}

/// The distinct points among points[indices], in double.
inline std::vector<Vec3d> distinct_points(std::span<const Vec3> points, std::array<std::size_t, 26> indices) {
  std::sort(indices.begin(), indices.end());
  std::vector<Vec3d> out;
  for (std::size_t k = 0; k < indices.size(); ++k) {
    if (k == 0 || indices[k] != indices[k - 1]) out.emplace_back(points[indices[k]]);
  }
  return out;
}

}  // namespace rayaccel::bv_detail
