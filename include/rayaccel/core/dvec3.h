// DVec3: a three-component double vector, the value type of the double-precision path (double/), for geometry far
// from the origin or spanning many orders of magnitude, where float's 24 bits lose too much.
#pragma once

#include <cmath>
#include <cstddef>

#include "rayaccel/core/vec3.h"

namespace rayaccel {

/// Vec3's members and operators again in double, a type of its own rather than a Vec3<T>: every module includes
/// vec3.h, and the float code keeps seeing no double types.
struct DVec3 {
  double x = 0.0, y = 0.0, z = 0.0;

  constexpr DVec3() = default;
  constexpr DVec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  /// Exact: every float is a double.
  constexpr explicit DVec3(const Vec3& v) : x(v.x), y(v.y), z(v.z) {}

  constexpr double operator[](std::size_t axis) const { return axis == 0 ? x : (axis == 1 ? y : z); }
  constexpr double& operator[](std::size_t axis) { return axis == 0 ? x : (axis == 1 ? y : z); }
  friend constexpr bool operator==(const DVec3&, const DVec3&) = default;
};

constexpr DVec3 operator+(const DVec3& a, const DVec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr DVec3 operator-(const DVec3& a, const DVec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr DVec3 operator*(const DVec3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
constexpr DVec3 operator*(double s, const DVec3& a) { return a * s; }
constexpr double dot(const DVec3& a, const DVec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr DVec3 cross(const DVec3& a, const DVec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const DVec3& a) { return std::sqrt(dot(a, a)); }
inline DVec3 abs(const DVec3& a) { return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}; }
inline bool is_finite(const DVec3& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
/// Index of the largest component (ties go to the lower axis).
constexpr int max_axis(const DVec3& a) { return (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2); }
/// Each component rounded to the nearest float: what the float path sees of a double point.
inline Vec3 to_float(const DVec3& a) { return {float(a.x), float(a.y), float(a.z)}; }

}  // namespace rayaccel
