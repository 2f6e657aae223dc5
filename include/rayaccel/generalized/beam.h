// Beam (Heckbert & Hanrahan 1984): a pyramid of rays with a convex cross-section, and the conservative outside
// tests that drive traversal by beams (both ways round: the separating-axis test for convex sets).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/vec3.h"
#include "rayaccel/geometry/triangle_box_overlap.h"

namespace rayaccel::generalized {

using detail::DVec3;

inline DVec3 to_d(const Vec3& v) { return {v.x, v.y, v.z}; }
inline double dnorm(const DVec3& v) { return std::sqrt(detail::ddot(v, v)); }
inline double dabs_dot(const DVec3& a, const DVec3& b) {
  return std::fabs(a.x * b.x) + std::fabs(a.y * b.y) + std::fabs(a.z * b.z);
}

/// Relative margin of every sign decided in double here. Each quantity is a few products and sums of float-exact or
/// once-rounded doubles, whose rounding is below 1e-15 of the magnitudes summed; a sign is trusted only when the value
/// clears 1e-9 of them, so a decision is never flipped by rounding (and is, at worst, "not proven").
inline constexpr double kBeamMargin = 1e-9;

/// A beam: the rays apex + t d (t >= 0) whose direction d lies on the inner side of every side plane. Side i passes
/// through the apex and is spanned by the edge rays edge[i] and edge[(i + 1) % side_count]; normal[i] points inward.
struct Beam {
  static constexpr int kMaxSides = 8;
  Vec3 apex;
  int side_count = 0;
  std::array<DVec3, kMaxSides> edge{};    ///< edge ray directions, in order around the cross-section
  std::array<DVec3, kMaxSides> normal{};  ///< inward normals of the side planes

  /// The beam through `count` (3..kMaxSides) edge directions in order around a convex cross-section that does not
  /// reach half a sphere. Returns a beam with side_count 0 (which contains nothing and proves nothing) when the edges
  /// are degenerate (parallel neighbours, a non-convex or reflex polygon, a non-finite value).
  static Beam through(const Vec3& apex, const DVec3* edges, int count);

  /// True when the ray direction d (from the apex) is proven inside: every side's value clears its rounding margin.
  bool contains(const Vec3& d) const;
  /// True when no point of the box (grown by `slack` on every side) lies in the beam.
  bool box_outside(const AABB& box, float slack) const;
  /// True when no point of the ball lies in the beam.
  bool sphere_outside(const Vec3& center, float radius) const;
  /// True when no ray of the beam meets the closed triangle.
  bool triangle_outside(const Vec3& a, const Vec3& b, const Vec3& c) const;
  /// True when every side's inward normal and every edge is set (a beam made by through() that succeeded).
  bool valid() const { return side_count >= 3; }
};

/// True when, for every ray of the beam, the triangle `front` is met strictly before any point of `back` (a set of
/// vertices and the segments between them, given by its box), by more than twice the rounding bound of the
/// watertight kernel's t for both (ray_triangle.h: at most 1/64 of a triangle's depth range along the ray plus
/// gamma(12) of its farthest vertex distance, each at most sqrt(3) times the Euclidean figure). Proven by `back`
/// lying entirely on the far side of front's plane (the apex on the near side) by more than that margin: a ray that
/// reaches `back` crosses the plane first, at front's hit point when it hits `front`.
bool beam_front_of(const Beam& beam, const Vec3& a, const Vec3& b, const Vec3& c, const AABB& back);

}  // namespace rayaccel::generalized
