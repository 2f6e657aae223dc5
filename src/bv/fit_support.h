// Private helpers shared by the bounding-volume fitters: a double-precision vector for fitting arithmetic.
#pragma once

#include <cmath>

#include "rayaccel/core/vec3.h"

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

}  // namespace rayaccel::bv_detail
