// Watertight ray/triangle intersection (Woop, Benthin, Wald 2013, "Watertight Ray/Triangle Intersection", JCGT 2(1)).
// Edge functions are computed in a ray-sheared space; a shared edge yields exactly negated values in its two
// triangles, so a ray through an edge or vertex of a closed mesh hits at least one triangle. No back-face culling.
// Triangles whose sheared coordinates leave [2^-40, 2^40] are first scaled by an exact power of two, so huge and
// tiny scenes neither overflow nor underflow (results in the normal range are unchanged, bit for bit).
#pragma once

#include <cmath>
#include <cstdint>
#include <initializer_list>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/core/vec3.h"

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

/// Edge functions, sign test and distance of a sheared triangle; `t_unscale` undoes a power-of-two scaling of it.
inline bool intersect_sheared_triangle(const PreparedRay& r, const ShearedTriangle& s, float t_unscale,
                                       std::uint32_t prim_id, Hit& hit) {
  float eu = s.cx * s.by - s.cy * s.bx;
  float ev = s.ax * s.cy - s.ay * s.cx;
  float ew = s.bx * s.ay - s.by * s.ax;
  if (eu == 0.0f || ev == 0.0f || ew == 0.0f) {
    // On an edge in single precision: decide in double, where these products are exact.
    eu = static_cast<float>(double(s.cx) * double(s.by) - double(s.cy) * double(s.bx));
    ev = static_cast<float>(double(s.ax) * double(s.cy) - double(s.ay) * double(s.cx));
    ew = static_cast<float>(double(s.bx) * double(s.ay) - double(s.by) * double(s.ax));
  }
  if ((eu < 0.0f || ev < 0.0f || ew < 0.0f) && (eu > 0.0f || ev > 0.0f || ew > 0.0f)) return false;
  const float det = eu + ev + ew;
  if (det == 0.0f) return false;
  const float az = r.shear_z * s.az;
  const float bz = r.shear_z * s.bz;
  const float cz = r.shear_z * s.cz;
  const float scaled_t = eu * az + ev * bz + ew * cz;
  const float inv_det = 1.0f / det;
  const float t = scaled_t * inv_det * t_unscale;
  if (!(t > r.t_min && t < hit.t)) return false;
  hit.t = t;
  hit.prim_id = prim_id;
  hit.u = ev * inv_det;
  hit.v = ew * inv_det;
  return true;
}

/// Scales a sheared triangle whose coordinates leave the safe range by a power of two (exact) and tests it.
inline bool intersect_rescaled_triangle(const PreparedRay& r, ShearedTriangle s, std::uint32_t prim_id, Hit& hit) {
  const float m = max_magnitude(s);
  if (!(m > 0.0f) || !std::isfinite(m)) return false;  // a point at the origin, or NaN/Inf coordinates
  const int exponent = std::ilogb(m);
  const float scale = std::ldexp(1.0f, -exponent);
  for (float* v : {&s.ax, &s.ay, &s.az, &s.bx, &s.by, &s.bz, &s.cx, &s.cy, &s.cz}) *v *= scale;
  return intersect_sheared_triangle(r, s, std::ldexp(1.0f, exponent), prim_id, hit);
}

/// Tests triangle (v0, v1, v2) and, when it is hit with r.t_min < t < hit.t, stores t, prim_id and the Embree-style
/// barycentrics (p = (1-u-v)*v0 + u*v1 + v*v2) in hit and returns true. Triangles with NaN vertices are never hit.
/// Requires -ffp-contract=off (see cmake/Warnings.cmake).
inline bool intersect_triangle(const PreparedRay& r, const Vec3& v0, const Vec3& v1, const Vec3& v2,
                               std::uint32_t prim_id, Hit& hit) {
  const Vec3 a = v0 - r.origin;
  const Vec3 b = v1 - r.origin;
  const Vec3 c = v2 - r.origin;
  const ShearedTriangle s{a[r.kx] - r.shear_x * a[r.kz], a[r.ky] - r.shear_y * a[r.kz], a[r.kz],
                          b[r.kx] - r.shear_x * b[r.kz], b[r.ky] - r.shear_y * b[r.kz], b[r.kz],
                          c[r.kx] - r.shear_x * c[r.kz], c[r.ky] - r.shear_y * c[r.kz], c[r.kz]};
  if (in_safe_range(s)) return intersect_sheared_triangle(r, s, 1.0f, prim_id, hit);
  return intersect_rescaled_triangle(r, s, prim_id, hit);
}

}  // namespace rayaccel
