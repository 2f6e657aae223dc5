// Affine3: a 3x4 affine transform (object to world), kept in double so that composing, inverting and mapping rays
// and boxes round only once, to float, at the end (as Embree and pbrt keep instance transforms: a linear part and a
// translation; pbrt-v4 Transform, Embree AffineSpace3fa).
#pragma once

#include <array>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/core/vec3.h"

namespace rayaccel {

struct Affine3 {
  /// Row-major 3x4: world = L * object + t, with L = columns 0..2 and t = column 3 of the rows.
  std::array<double, 12> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};

  static Affine3 identity() { return {}; }
  static Affine3 translation(double x, double y, double z);
  static Affine3 scaling(double x, double y, double z);
  /// Rotation by `radians` about `axis` (right-handed; the axis need not be unit length). Throws Error for a zero
  /// or non-finite axis.
  static Affine3 rotation(const Vec3& axis, double radians);
  /// From 12 floats, row-major 3x4 (the layout of Embree's RTC_FORMAT_FLOAT3X4_ROW_MAJOR).
  static Affine3 from_rows(const std::array<float, 12>& rows);

  double operator()(int row, int col) const { return m[static_cast<std::size_t>(row * 4 + col)]; }
  double& operator()(int row, int col) { return m[static_cast<std::size_t>(row * 4 + col)]; }

  bool is_finite() const;
  /// True when every entry is exactly that of the identity (a -0 counts as 0).
  bool is_identity() const { return m == identity().m; }
  /// Determinant of the linear part; negative for a mirroring transform.
  double determinant() const;
  /// The inverse transform. Throws Error for a non-finite transform or a singular one (|det| <= 1e-12 * s^3, s the
  /// largest entry of the linear part, or an inverse that overflows), naming the determinant.
  Affine3 inverse() const;

  /// The point or direction mapped, in double (no rounding beyond the double products and sums).
  std::array<double, 3> apply_point(const Vec3& p) const;
  std::array<double, 3> apply_vector(const Vec3& v) const;
};

/// a * b maps by b first, then by a.
Affine3 operator*(const Affine3& a, const Affine3& b);

/// Rounds a double triple to the nearest floats.
Vec3 round_to_float(const std::array<double, 3>& p);

/// The world box of `box` under `transform`: its 8 corners mapped in double, the bounds rounded outward to float and
/// widened by one more ulp, so the float box contains every point of the exactly transformed box. Empty stays empty.
AABB transform_box(const Affine3& transform, const AABB& box);

/// The ray in the space `world_to_object` maps to: origin and direction mapped in double and rounded to nearest
/// float once each; t_min and t_max are kept, because the direction is mapped linearly and not normalised, so a
/// point at parameter t on the world ray maps to the point at the same t on the object ray (up to that rounding).
Ray transform_ray(const Affine3& world_to_object, const Ray& ray);

}  // namespace rayaccel
