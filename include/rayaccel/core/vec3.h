// Vec3: a three-component float vector, the one value type every module shares.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace rayaccel {

struct Vec3 {
  float x = 0.0f, y = 0.0f, z = 0.0f;

  constexpr Vec3() = default;
  constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
  constexpr explicit Vec3(float s) : x(s), y(s), z(s) {}

  constexpr float operator[](std::size_t axis) const { return axis == 0 ? x : (axis == 1 ? y : z); }
  constexpr float& operator[](std::size_t axis) { return axis == 0 ? x : (axis == 1 ? y : z); }

  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
  constexpr Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  constexpr Vec3& operator*=(float s) { x *= s; y *= s; z *= s; return *this; }
  friend constexpr bool operator==(const Vec3&, const Vec3&) = default;
};

constexpr Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr Vec3 operator*(const Vec3& a, const Vec3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
constexpr Vec3 operator*(const Vec3& a, float s) { return {a.x * s, a.y * s, a.z * s}; }
constexpr Vec3 operator*(float s, const Vec3& a) { return a * s; }
constexpr Vec3 operator/(const Vec3& a, float s) { return {a.x / s, a.y / s, a.z / s}; }

constexpr float dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(const Vec3& a) { return std::sqrt(dot(a, a)); }
/// Unit vector along a; the zero vector stays zero (never NaN from a division by zero).
inline Vec3 normalize(const Vec3& a) {
  const float len = length(a);
  return len > 0.0f ? a / len : Vec3{};
}
constexpr Vec3 min(const Vec3& a, const Vec3& b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
constexpr Vec3 max(const Vec3& a, const Vec3& b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
inline Vec3 abs(const Vec3& a) { return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}; }
inline bool is_finite(const Vec3& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
constexpr float max_component(const Vec3& a) { return std::max(a.x, std::max(a.y, a.z)); }
constexpr float min_component(const Vec3& a) { return std::min(a.x, std::min(a.y, a.z)); }
/// Index of the largest component (ties go to the lower axis).
constexpr int max_axis(const Vec3& a) { return (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2); }
/// v[axis] for an axis known only at run time, without branches (Vec3's operator[] compares the axis, and a ray's
/// kx, ky, kz vary from ray to ray): an indexed load from a copy.
inline float component(const Vec3& v, int axis) {
  const float c[3] = {v.x, v.y, v.z};
  return c[axis];
}

}  // namespace rayaccel
