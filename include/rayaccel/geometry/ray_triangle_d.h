// Watertight ray/triangle intersection in double (Woop, Benthin, Wald 2013, JCGT 2(1)) with the float kernel's
// rules carried over (ray_triangle.h): error-bounded edge functions, exact signs inside the bound (Shewchuk 1997).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "rayaccel/core/ray_d.h"
#include "rayaccel/geometry/exact_edge.h"

namespace rayaccel {

/// Constants of the double kernel's error bounds (double_gamma(n): the relative bound of n roundings).
struct WatertightBoundsD {
  /// Multiplies a bound computed in double to cover the rounding of its own few operations.
  static constexpr double kSlack = 1.0 + 0x1p-40;
  /// Added to the edge error bound: far above any absolute error the double domain allows to underflow.
  static constexpr double kEdgeFloor = 0x1p-900;
  /// An edge error bound above |det| / kIllConditioned sends the triangle to the exact edge functions (float's rule).
  static constexpr double kIllConditioned = 192.0;
};

/// Tests triangle (v0, v1, v2) (vertices in the double domain) and, when it is hit with r.t_min < t < hit.t (t
/// clearing t_min by its error bound), stores t, prim_id and the barycentrics (p = (1-u-v)*v0 + u*v1 + v*v2) in hit
/// and returns true. Void rays, and triangles with NaN vertices or vertices outside the double domain that need the
/// exact edge functions, are never hit.
inline bool intersect_triangle(const PreparedRayD& r, const DVec3& v0, const DVec3& v1, const DVec3& v2,
                               std::uint32_t prim_id, HitD& hit) {
  const DVec3 a = v0 - r.origin;
  const DVec3 b = v1 - r.origin;
  const DVec3 c = v2 - r.origin;
  const double ax = a[r.kx] - r.shear_x * a[r.kz], ay = a[r.ky] - r.shear_y * a[r.kz], az = a[r.kz];
  const double bx = b[r.kx] - r.shear_x * b[r.kz], by = b[r.ky] - r.shear_y * b[r.kz], bz = b[r.kz];
  const double cx = c[r.kx] - r.shear_x * c[r.kz], cy = c[r.ky] - r.shear_y * c[r.kz], cz = c[r.kz];
  double u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;

  // Error bound of the edge functions (the float kernel's TriangleErrorBounds with u = 2^-53): a sheared coordinate
  // is off the exact one of the double ray by at most gamma(3) max|x| + gamma(5) |s_x| max|z|.
  const double max_x = std::max({std::fabs(ax), std::fabs(bx), std::fabs(cx)});
  const double max_y = std::max({std::fabs(ay), std::fabs(by), std::fabs(cy)});
  const double max_z = std::max({std::fabs(az), std::fabs(bz), std::fabs(cz)});
  const double dx = double_gamma(3) * max_x + double_gamma(5) * std::fabs(r.shear_x) * max_z;
  const double dy = double_gamma(3) * max_y + double_gamma(5) * std::fabs(r.shear_y) * max_z;
  double edge_error = (2.0 * double_gamma(2) * max_x * max_y + 2.0 * ((dx * max_y + dy * max_x) + dx * dy)) *
                          WatertightBoundsD::kSlack +
                      WatertightBoundsD::kEdgeFloor;
  const double lo = std::min({u, v, w}), hi = std::max({u, v, w});
  if (lo < -edge_error && hi > edge_error) return false;  // surely of opposite signs

  double det = (u + v) + w;
  const bool in_band = std::fabs(u) <= edge_error || std::fabs(v) <= edge_error || std::fabs(w) <= edge_error;
  if (in_band || edge_error * WatertightBoundsD::kIllConditioned >= std::fabs(det)) {
    if (r.is_void() || !in_double_domain(v0) || !in_double_domain(v1) || !in_double_domain(v2)) return false;
    double error = 0.0;
    const auto edge = [&](const DVec3& p, const DVec3& q) {
      const ExactEdge x = exact_edge_function(r.origin, r.direction, r.kx, r.ky, r.kz, p, q);
      error = std::max(error, x.error);
      return x.sign == 0 ? 0.0 : x.value;
    };
    u = edge(v2, v1);
    v = edge(v0, v2);
    w = edge(v1, v0);
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
    edge_error = error * WatertightBoundsD::kSlack + WatertightBoundsD::kEdgeFloor;
    det = (u + v) + w;
  }
  if (det == 0.0) return false;
  const double zs = r.shear_z;
  const double inv_det = 1.0 / det;
  const double t = (((u * (zs * az) + v * (zs * bz)) + w * (zs * cz))) * inv_det;
  if (!(t > r.t_min && t < hit.t)) return false;
  const double abs_zs = std::fabs(zs);
  const double range_zt = abs_zs * (std::max({az, bz, cz}) - std::min({az, bz, cz}));
  const double t_error = ((3.0 * edge_error) * std::fabs(inv_det) * range_zt + double_gamma(12) * abs_zs * max_z) *
                         WatertightBoundsD::kSlack;
  if (!(t > r.t_min + t_error)) return false;
  hit.t = t;
  hit.prim_id = prim_id;
  hit.u = v * inv_det;
  hit.v = w * inv_det;
  return true;
}

}  // namespace rayaccel
