// Watertight ray/triangle intersection (Woop, Benthin, Wald 2013, JCGT 2(1)) with every hit/miss decision exact for
// the float inputs: float edge functions with a rounding-error bound (pbrt 3rd ed., 3.9.6), recomputed exactly
// inside it (exact_edge.h, Shewchuk 1997), and a hit only where t clears t_min by a bound on t's error.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>

#include "rayaccel/core/float_rounding.h"
#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/core/vec3.h"
#include "rayaccel/geometry/exact_edge.h"

namespace rayaccel {

/// The triangle relative to the ray origin in the ray's sheared frame: x, y after the shear, z before it.
struct ShearedTriangle {
  float ax, ay, az, bx, by, bz, cx, cy, cz;
};

inline constexpr float kShearSafeMax = 0x1p40f;
inline constexpr float kShearSafeMin = 0x1p-40f;

/// std::fmax(m, v) written out: without -ffinite-math-only GCC calls libm's fmaxf for it (measured: a quarter of
/// the time of scalar triangle tests), this compiles to compares. A NaN operand yields the other one.
inline float fmax_inline(float m, float v) { return (v > m || m != m) ? v : m; }
/// std::fmin(m, v) written out, as fmax_inline.
inline float fmin_inline(float m, float v) { return (v < m || m != m) ? v : m; }

/// Largest magnitude of the nine coordinates (NaN coordinates are ignored unless all are NaN).
inline float max_magnitude(const ShearedTriangle& s) {
  float m = std::fabs(s.ax);
  for (float v : {s.ay, s.az, s.bx, s.by, s.bz, s.cx, s.cy, s.cz}) m = fmax_inline(m, std::fabs(v));
  return m;
}

/// True when every sheared coordinate is small enough and the largest big enough for the float kernel: products of
/// three coordinates then stay within float range (2^120 > |t*det| and 2^-120 < it).
inline bool in_safe_range(const ShearedTriangle& s) {
  const float m = max_magnitude(s);
  return m <= kShearSafeMax && m >= kShearSafeMin;
}

/// The absolute part of a shear's rounding error: d_x / d_z below FLT_MIN rounds to a subnormal (or zero) whose
/// error is not relative to it (at most 2^-150), so a ray whose direction is all but parallel to a plane of axes
/// still bounds its sheared coordinates (fuzz corpus shear-underflow-grazing-ray: a shear of 6e-50 read as 0).
inline constexpr float kShearAbsoluteError = 0x1p-149f;
/// The factor of max|z| in the error bound of a sheared coordinate: gamma(5) |shear| + kShearAbsoluteError (see
/// TriangleErrorBounds).
inline float shear_error(float shear) { return float_gamma(5) * std::fabs(shear) + kShearAbsoluteError; }

/// Constants of the error bounds (float_gamma(n): the relative bound of n roundings).
struct WatertightBounds {
  /// Multiplies a bound computed in float to cover the rounding of its own few operations.
  static constexpr float kSlack = 1.0f + 0x1p-16f;
  /// Added to the edge error bound in the safe range: covers the absolute error of products that underflow (below
  /// 2^-149 * 2^42 there) with room to spare.
  static constexpr float kEdgeFloor = 0x1p-100f;
  /// A triangle whose edge error bound exceeds |det| / kIllConditioned (3 * 64: its t would be off by more than 1/64
  /// of its depth range) is decided and measured with exact edge functions.
  static constexpr float kIllConditioned = 192.0f;
  /// Relative error of rounding an edge function known to double precision to float, and its absolute floor.
  static constexpr float kExactRelative = 0x1p-22f;
  static constexpr float kExactFloor = 0x1p-148f;
  /// Float computes t only when the largest depth, its products with |det| and its value in world units are at
  /// least this (see depth_in_float_range()).
  static constexpr float kDepthMin = 0x1p-100f;
};

/// The largest magnitudes of a sheared triangle's coordinates (x, y after the shear, z before it), its depth range
/// (lo_z, hi_z: signed) and the bound on the error of its float edge functions against the exact ones.
struct TriangleErrorBounds {
  float max_x, max_y, max_z, lo_z, hi_z;
  float edge_error;

  /// `underflow` bounds the absolute error of one sheared coordinate from products that underflowed (0 in the safe
  /// range, where kEdgeFloor covers it; 2^-149 times the scale after rescaling).
  TriangleErrorBounds(const PreparedRay& r, const ShearedTriangle& s, float underflow) {
    max_x = fmax_inline(std::fabs(s.ax), fmax_inline(std::fabs(s.bx), std::fabs(s.cx)));
    max_y = fmax_inline(std::fabs(s.ay), fmax_inline(std::fabs(s.by), std::fabs(s.cy)));
    max_z = fmax_inline(std::fabs(s.az), fmax_inline(std::fabs(s.bz), std::fabs(s.cz)));
    lo_z = fmin_inline(s.az, fmin_inline(s.bz, s.cz));
    hi_z = fmax_inline(s.az, fmax_inline(s.bz, s.cz));
    // A sheared coordinate x = a_x - s_x a_z against the exact X of the float ray (the shear s_x = d_x / d_z rounded,
    // |s_x| <= 1): |x - X| <= gamma(3) max|x| + shear_error(s_x) max|z|. Then for an edge function,
    // |e - E| <= 2 gamma(2) max|x| max|y| + 2 (dx max|y| + dy max|x| + dx dy).
    const float dx = (float_gamma(3) * max_x + shear_error(r.shear_x) * max_z) + underflow;
    const float dy = (float_gamma(3) * max_y + shear_error(r.shear_y) * max_z) + underflow;
    edge_error = (2.0f * float_gamma(2) * max_x * max_y + 2.0f * ((dx * max_y + dy * max_x) + dx * dy)) *
                     WatertightBounds::kSlack +
                 WatertightBounds::kEdgeFloor;
  }
};

/// Bound on the error of the t computed from edge functions with error at most `edge_error` and 1 / det = inv_det:
/// 3 edge_error |inv_det| times the depth range, plus gamma(12) of the largest vertex distance, measured along the
/// dominant axis in the units of `s`, then brought to the ray's t as t is (times t_unscale, then |shear_z|).
inline float t_error_bound(const PreparedRay& r, const TriangleErrorBounds& b, float edge_error, float inv_det,
                           float t_unscale) {
  const float depth_error =
      (((3.0f * edge_error) * std::fabs(inv_det)) * (b.hi_z - b.lo_z) + float_gamma(12) * b.max_z) *
      WatertightBounds::kSlack;
  return (depth_error * t_unscale) * std::fabs(r.shear_z);
}

/// True when t and its bound can be computed in float from depths at most `max_z` in magnitude (in the units of a
/// sheared triangle that t_unscale brings to world units), with edge functions summing to det: the products of edge
/// functions and depths (up to |det| max_z), the depth they give and its error bound (gamma(12) max_z) then lose at
/// most 2^-149 to underflow, far below the bound. Else (max_z = 0 included) t is computed in double.
inline bool depth_in_float_range(float det, float max_z, float t_unscale) {
  constexpr float k = WatertightBounds::kDepthMin;
  return max_z >= k && std::fabs(det) * max_z >= k && max_z * t_unscale >= k;
}

/// An edge function's exact value rounded to float, keeping its sign: a nonzero value too small for float becomes
/// the smallest subnormal of its sign instead of a zero (which would put the ray on the edge).
inline float edge_to_float(double e) {
  const auto f = static_cast<float>(e);
  if (f != 0.0f || e == 0.0) return f;
  return e > 0.0 ? std::numeric_limits<float>::denorm_min() : -std::numeric_limits<float>::denorm_min();
}

/// The triangle in world space, for edges that float cannot decide, and the factor (a power of two squared) that
/// brings its exact edge functions to the scale of the sheared float triangle.
struct TriangleForEdges {
  const Vec3& v0;
  const Vec3& v1;
  const Vec3& v2;
  double edge_scale = 1.0;
};

/// The three edge functions of a sheared triangle (u, v, w: opposite vertex a, b, c).
struct EdgeFunctions {
  float u, v, w;
  /// In float.
  explicit EdgeFunctions(const ShearedTriangle& s)
      : u(s.cx * s.by - s.cy * s.bx), v(s.ax * s.cy - s.ay * s.cx), w(s.bx * s.ay - s.by * s.ax) {}
  /// Some edge function below zero and another above it (NaN counts as neither): the ray misses.
  bool mixed_signs() const { return (u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f); }
  /// Some edge function below -error and another above +error: the exact ones have opposite signs too.
  bool surely_mixed(float error) const {
    const float lo = fmin_inline(u, fmin_inline(v, w)), hi = fmax_inline(u, fmax_inline(v, w));
    return lo < -error && hi > error;
  }
  /// Some edge function within `error` of zero: float cannot give its sign.
  bool in_band(float error) const {
    return std::fabs(u) <= error || std::fabs(v) <= error || std::fabs(w) <= error;
  }
  float max_magnitude() const { return fmax_inline(std::fabs(u), fmax_inline(std::fabs(v), std::fabs(w))); }
};

/// Replaces `e` with the edge functions of the exact signs (exact_edge.h) rounded to float, and returns the bound
/// on their error (the ray must not be void). All three (and the bound) may be scaled by one power of two first, so
/// that they round to normal floats: t and the barycentrics are ratios of them, unchanged by a common factor, and
/// keep their precision even for triangles whose edge functions would be subnormal (a triangle 1e-21 across).
inline float exact_edge_functions(const PreparedRay& r, const TriangleForEdges& t, EdgeFunctions& e) {
  double error = 0.0;
  const auto edge = [&](const Vec3& p, const Vec3& q) {
    const ExactEdge x = exact_edge_function(r.origin, r.direction, r.kx, r.ky, r.kz, p, q);
    error = std::max(error, x.error * t.edge_scale);
    return x.sign == 0 ? 0.0 : x.value * t.edge_scale;
  };
  double u = edge(t.v2, t.v1), v = edge(t.v0, t.v2), w = edge(t.v1, t.v0);
  const double largest = std::max({std::fabs(u), std::fabs(v), std::fabs(w)});
  if (largest > 0.0 && largest < 0x1p-60) {
    const int k = -std::ilogb(largest);
    u = std::ldexp(u, k);
    v = std::ldexp(v, k);
    w = std::ldexp(w, k);
    error = std::ldexp(error, k);
  }
  e.u = edge_to_float(u);
  e.v = edge_to_float(v);
  e.w = edge_to_float(w);
  return (round_up_to_float(error) + e.max_magnitude() * WatertightBounds::kExactRelative) * WatertightBounds::kSlack +
         WatertightBounds::kExactFloor;
}

/// Decides and measures a sheared triangle (in the units of `s`; `t_unscale` undoes a power-of-two scaling) whose
/// float edge functions `e`, with bounds `b`, are not surely of opposite signs.
inline bool finish_sheared_triangle(const PreparedRay& r, const ShearedTriangle& s, EdgeFunctions e,
                                    const TriangleErrorBounds& b, float t_unscale, const TriangleForEdges& world,
                                    std::uint32_t prim_id, Hit& hit) {
  float det = (e.u + e.v) + e.w;
  float edge_error = b.edge_error;
  if (e.in_band(edge_error) || edge_error * WatertightBounds::kIllConditioned >= std::fabs(det)) {
    if (r.is_void()) return false;
    edge_error = exact_edge_functions(r, world, e);
    if (e.mixed_signs()) return false;
    det = (e.u + e.v) + e.w;
  }
  if (det == 0.0f) return false;
  const float inv_det = 1.0f / det;
  float t;
  if (depth_in_float_range(det, b.max_z, t_unscale)) {
    // The hit's depth along the dominant axis in the units of `s`, brought to the ray's t last: products of three
    // coordinates stay in float's range (in_safe_range), and the one multiplication by shear_z = 1 / d[kz] comes
    // after the scale is undone, so a long direction (tiny shear_z) or a short one (huge shear_z) underflows or
    // overflows only when t itself does.
    const float scaled_depth = (e.u * s.az + e.v * s.bz) + e.w * s.cz;
    t = ((scaled_depth * inv_det) * t_unscale) * r.shear_z;
    if (!(t > r.t_min && t < hit.t)) return false;
    if (!(t > r.t_min + t_error_bound(r, b, edge_error, inv_det, t_unscale))) return false;
  } else {
    // Depths tiny against the other coordinates, or in world units: the same t and bound in double, from the world
    // depths (those of `s` may have underflowed when it was rescaled). Products of floats are exact in double.
    const auto kz = static_cast<std::size_t>(r.kz);
    const double origin_z = r.origin[kz];
    const double az = world.v0[kz] - origin_z, bz = world.v1[kz] - origin_z, cz = world.v2[kz] - origin_z;
    const double inv_det_d = 1.0 / double(det);
    const double depth = (double(e.u) * az + double(e.v) * bz) + double(e.w) * cz;
    t = static_cast<float>(depth * inv_det_d * double(r.shear_z));
    if (!(t > r.t_min && t < hit.t)) return false;
    const double depth_range = std::max({az, bz, cz}) - std::min({az, bz, cz});
    const double max_z = std::max({std::fabs(az), std::fabs(bz), std::fabs(cz)});
    const double error = ((3.0 * edge_error) * std::fabs(inv_det_d) * depth_range + double(float_gamma(12)) * max_z) *
                         double(WatertightBounds::kSlack) * std::fabs(double(r.shear_z));
    if (!(double(t) > double(r.t_min) + error)) return false;
  }
  hit.t = t;
  hit.prim_id = prim_id;
  hit.u = e.v * inv_det;
  hit.v = e.w * inv_det;
  return true;
}

/// Scales a sheared triangle whose coordinates leave the safe range by a power of two (exact) and tests it.
inline bool intersect_rescaled_triangle(const PreparedRay& r, ShearedTriangle s, const TriangleForEdges& world,
                                        std::uint32_t prim_id, Hit& hit) {
  const float m = max_magnitude(s);
  if (!(m > 0.0f) || !std::isfinite(m)) return false;  // a point at the origin, or NaN/Inf coordinates
  const int exponent = std::ilogb(m);
  const float scale = std::ldexp(1.0f, -exponent);
  for (float* v : {&s.ax, &s.ay, &s.az, &s.bx, &s.by, &s.bz, &s.cx, &s.cy, &s.cz}) *v *= scale;
  const EdgeFunctions e(s);
  const TriangleErrorBounds b(r, s, std::ldexp(1.0f, -149 - exponent));
  if (e.surely_mixed(b.edge_error)) return false;
  const TriangleForEdges scaled{world.v0, world.v1, world.v2, std::ldexp(1.0, -2 * exponent)};
  return finish_sheared_triangle(r, s, e, b, std::ldexp(1.0f, exponent), scaled, prim_id, hit);
}

/// Tests triangle (v0, v1, v2) and, when it is hit with r.t_min < t < hit.t (t clearing t_min by its error bound),
/// stores t, prim_id and the Embree-style barycentrics (p = (1-u-v)*v0 + u*v1 + v*v2) in hit and returns true.
/// Triangles with NaN vertices are never hit.
inline bool intersect_triangle(const PreparedRay& r, const Vec3& v0, const Vec3& v1, const Vec3& v2,
                               std::uint32_t prim_id, Hit& hit) {
  const Vec3 a = v0 - r.origin;
  const Vec3 b = v1 - r.origin;
  const Vec3 c = v2 - r.origin;
  const ShearedTriangle s{a[r.kx] - r.shear_x * a[r.kz], a[r.ky] - r.shear_y * a[r.kz], a[r.kz],
                          b[r.kx] - r.shear_x * b[r.kz], b[r.ky] - r.shear_y * b[r.kz], b[r.kz],
                          c[r.kx] - r.shear_x * c[r.kz], c[r.ky] - r.shear_y * c[r.kz], c[r.kz]};
  // Edge functions of opposite signs beyond their error bound are a miss in any range (the bound is then finite).
  // The rest is decided in the safe range, rescaled if need be.
  const EdgeFunctions e(s);
  const TriangleErrorBounds bounds(r, s, 0.0f);
  if (e.surely_mixed(bounds.edge_error)) return false;
  const TriangleForEdges world{v0, v1, v2};
  if (in_safe_range(s)) return finish_sheared_triangle(r, s, e, bounds, 1.0f, world, prim_id, hit);
  return intersect_rescaled_triangle(r, s, world, prim_id, hit);
}

}  // namespace rayaccel
