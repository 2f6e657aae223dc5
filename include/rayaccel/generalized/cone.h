// Cone (Amanatides 1984): rays from one apex within a half-angle of an axis, its conservative tests against balls
// and boxes, and a fixed pattern of directions that estimates the fraction of the cone a primitive covers.
#pragma once

#include <limits>
#include <vector>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/generalized/beam.h"

namespace rayaccel::generalized {

/// The points apex + s d with |d| = 1, angle(d, axis) <= half_angle and t_min <= s <= t_max (s is the distance from
/// the apex, as t of a ray with a unit direction).
struct Cone {
  Vec3 apex;
  Vec3 axis{0.0f, 0.0f, 1.0f};  ///< any nonzero length
  float half_angle = 0.01f;     ///< radians, in (0, pi / 2)
  float t_min = 0.0f;
  float t_max = std::numeric_limits<float>::infinity();
};

/// The direction at polar angle acos(1 - s (1 - cos(half_angle))) from `axis` (nonzero) and azimuth 2 pi t about it:
/// for s and t uniform in [0, 1), uniform in solid angle within the cone (so is an even spread of s).
Vec3 cone_direction(const Vec3& axis, double half_angle, double s, double t);

/// A checked cone with its derived constants. Throws Error naming the value for a non-finite apex, a zero or
/// non-finite axis, a half-angle outside (0, pi / 2), or a t range that is NaN, negative or empty.
class PreparedCone {
 public:
  explicit PreparedCone(const Cone& cone);

  const Cone& cone() const { return cone_; }
  /// True only when no point of the ball lies in the cone: exact (up to a margin of 1e-9 relative) for the infinite
  /// cone; the distance range cuts by the ball's nearest and farthest distances from the apex (conservative).
  bool sphere_outside(const Vec3& center, float radius) const;
  /// True only when no point of the box (grown by slack) lies in the cone: its bounding ball is outside, or it is
  /// outside the square pyramid around the cone.
  bool box_outside(const AABB& box, float slack) const;
  /// True only when no point of the triangle lies in the cone (its bounding ball, or the pyramid, as above).
  bool triangle_outside(const Vec3& a, const Vec3& b, const Vec3& c) const;
  /// `count` unit directions inside the cone, spread evenly over its solid angle (equal-area rings, a golden-angle
  /// spiral: sample k at cos(angle) = 1 - (k + 1/2) / count * (1 - cos(half_angle))).
  std::vector<Vec3> pattern(int count) const;
  /// The ray of one pattern direction over the cone's range.
  Ray ray(const Vec3& direction) const { return Ray{cone_.apex, cone_.t_min, direction, cone_.t_max}; }
  /// The cone's orthonormal frame: u, v across the axis, axis along it (right-handed).
  const DVec3& u() const { return u_; }
  const DVec3& v() const { return v_; }
  const DVec3& axis() const { return axis_; }

 private:
  Cone cone_;
  DVec3 axis_;  ///< unit
  DVec3 u_, v_;
  Beam pyramid_;
};

}  // namespace rayaccel::generalized
