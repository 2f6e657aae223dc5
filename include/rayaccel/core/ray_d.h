// The double-precision ray, its per-ray constants and its hit record (RayD, PreparedRayD, HitD), after Woop, Benthin,
// Wald 2013 (shear) and Ize 2013 (slab test), and the double domain every input of the double path lies in.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "rayaccel/core/dvec3.h"
#include "rayaccel/core/hit.h"

namespace rayaccel {

// The double domain: every coordinate the double path takes (vertices, ray origins, ray directions) is 0 or has a
// magnitude in [2^-64, 2^64] (about 5.4e-20 to 1.8e19). Inside it, every product the exact edge functions form
// (geometry/exact_edge.h) stays far from double's overflow and underflow, so their signs are exact; DoubleScene
// rejects vertices outside it with an Error, and a ray with a component outside it is void.

inline constexpr double kDoubleDomainMax = 0x1p64;
inline constexpr double kDoubleDomainMin = 0x1p-64;

/// True for 0 and for magnitudes in [2^-64, 2^64]; false for NaN, infinities and everything else.
inline bool in_double_domain(double x) {
  const double a = std::fabs(x);
  return a == 0.0 || (a >= kDoubleDomainMin && a <= kDoubleDomainMax);
}
inline bool in_double_domain(const DVec3& v) {
  return in_double_domain(v.x) && in_double_domain(v.y) && in_double_domain(v.z);
}

/// gamma(n) = n u / (1 - n u), u = 2^-53: the relative rounding bound of n double operations (pbrt, section 3.9.1).
constexpr double double_gamma(int n) { return double(n) * 0x1p-53 / (1.0 - double(n) * 0x1p-53); }

/// A ray in double; the direction need not be normalized and t is measured in units of its length.
struct RayD {
  DVec3 origin;
  double t_min = 0.0;
  DVec3 direction{0.0, 0.0, 1.0};
  double t_max = std::numeric_limits<double>::infinity();
};

/// False for a void ray: an origin or direction component outside the double domain (NaN and infinities included),
/// a zero direction, a NaN t bound, or t_max < t_min.
inline bool is_valid_ray(const RayD& ray) {
  const DVec3& d = ray.direction;
  return in_double_domain(ray.origin) && in_double_domain(d) && (d.x != 0.0 || d.y != 0.0 || d.z != 0.0) &&
         !std::isnan(ray.t_min) && !std::isnan(ray.t_max) && ray.t_min <= ray.t_max;
}

/// Per-ray constants of the double kernels, as PreparedRay: a void ray gets the empty interval (t_min = +inf,
/// t_max = -inf), so every test rejects it.
struct PreparedRayD {
  DVec3 origin;
  DVec3 direction;
  DVec3 inv_direction;  ///< 1/d per axis; +-inf for +-0 components
  int negative[3];      ///< 1 when the direction's sign bit is set (also for -0)
  double t_min;
  double t_max;  ///< inclusive
  int kx, ky, kz;  ///< kz: the dominant axis; (kx, ky) in winding-preserving order
  double shear_x, shear_y, shear_z;

  bool is_void() const { return !(t_min <= t_max); }

  explicit PreparedRayD(const RayD& ray) : origin(ray.origin), direction(ray.direction) {
    const DVec3& d = direction;
    if (is_valid_ray(ray)) {
      t_min = ray.t_min;
      t_max = ray.t_max;
    } else {
      t_min = std::numeric_limits<double>::infinity();
      t_max = -std::numeric_limits<double>::infinity();
    }
    for (int a = 0; a < 3; ++a) {
      inv_direction[a] = 1.0 / d[a];
      negative[a] = std::signbit(d[a]) ? 1 : 0;
    }
    kz = max_axis(abs(d));
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (d[kz] < 0.0) { const int tmp = kx; kx = ky; ky = tmp; }
    const double dz = d[kz] != 0.0 ? d[kz] : 1.0;  // only a void ray has d[kz] == 0
    shear_x = d[kx] / dz;
    shear_y = d[ky] / dz;
    shear_z = 1.0 / dz;
  }
};

/// The closest-hit record in double {t, prim_id, u, v}; barycentrics as Hit's: p = (1-u-v)*v0 + u*v1 + v*v2.
/// Hit's members again in double, a type of its own rather than a Hit<T>: its layout is the .hits64 record (a padding
/// word after prim_id), and float code keeps seeing no double types.
struct HitD {
  /// While tracing: the exclusive upper bound of t (see begin()). After finish(): the distance, or +inf for a miss.
  double t = std::numeric_limits<double>::infinity();
  std::uint32_t prim_id = kInvalidPrimId;
  double u = 0.0;
  double v = 0.0;

  bool found() const { return prim_id != kInvalidPrimId; }
  /// A hit counts when t_min < t <= t_max: tracing keeps the exclusive bound hit.t, starting just above t_max.
  static HitD begin(const PreparedRayD& ray) {
    HitD h;
    h.t = std::nextafter(ray.t_max, std::numeric_limits<double>::infinity());
    return h;
  }
  /// Misses get t = +inf and u = v = 0.
  void finish() {
    if (!found()) { t = std::numeric_limits<double>::infinity(); u = 0.0; v = 0.0; }
  }
};

}  // namespace rayaccel
