// AABB: axis-aligned bounding box with inclusive bounds; the default box is empty (lo = +inf, hi = -inf).
#pragma once

#include <limits>

#include "rayaccel/core/vec3.h"

namespace rayaccel {

struct AABB {
  Vec3 lo{std::numeric_limits<float>::infinity()};
  Vec3 hi{-std::numeric_limits<float>::infinity()};

  constexpr AABB() = default;
  constexpr AABB(const Vec3& lo_, const Vec3& hi_) : lo(lo_), hi(hi_) {}
  static constexpr AABB empty() { return {}; }
  static constexpr AABB of_point(const Vec3& p) { return {p, p}; }

  /// True when the box holds no point (any lo > hi, or NaN bounds).
  constexpr bool is_empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
  bool is_finite() const { return rayaccel::is_finite(lo) && rayaccel::is_finite(hi); }

  constexpr AABB& extend(const Vec3& p) { lo = min(lo, p); hi = max(hi, p); return *this; }
  constexpr AABB& extend(const AABB& b) { lo = min(lo, b.lo); hi = max(hi, b.hi); return *this; }

  constexpr Vec3 extent() const { return hi - lo; }
  constexpr Vec3 center() const { return (lo + hi) * 0.5f; }
  /// Surface area; 0 for an empty box.
  constexpr float surface_area() const {
    if (is_empty()) return 0.0f;
    const Vec3 e = extent();
    return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
  constexpr float volume() const {
    if (is_empty()) return 0.0f;
    const Vec3 e = extent();
    return e.x * e.y * e.z;
  }
  constexpr int largest_axis() const { return max_axis(extent()); }
  constexpr bool contains(const Vec3& p) const {
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
  }
  constexpr bool contains(const AABB& b) const { return b.is_empty() || (contains(b.lo) && contains(b.hi)); }
  constexpr bool overlaps(const AABB& b) const {
    return lo.x <= b.hi.x && b.lo.x <= hi.x && lo.y <= b.hi.y && b.lo.y <= hi.y && lo.z <= b.hi.z && b.lo.z <= hi.z;
  }
  friend constexpr bool operator==(const AABB&, const AABB&) = default;
};

constexpr AABB merge(const AABB& a, const AABB& b) { return AABB(a).extend(b); }
constexpr AABB intersection(const AABB& a, const AABB& b) { return {max(a.lo, b.lo), min(a.hi, b.hi)}; }

}  // namespace rayaccel
