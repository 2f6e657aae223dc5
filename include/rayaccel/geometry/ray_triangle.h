// Watertight ray/triangle intersection (Woop, Benthin, Wald 2013, "Watertight Ray/Triangle Intersection", JCGT 2(1)).
// Edge functions are computed in a ray-sheared space; a shared edge yields exactly negated values in its two
// triangles, so a ray through an edge or vertex of a closed mesh hits at least one triangle. No back-face culling.
// An edge function that is exactly zero in float is decided again in double from the vertices (Woop et al. fall
// back to double too; computing the shear in double as well keeps underflow near 0 from making false hits). Only that
// edge is recomputed: a nonzero float edge function has the exact sign of its products' difference (rounding is
// monotone, so the two products cannot swap order), so each edge's sign is a function of the edge and the ray alone,
// the same in both triangles that share it, and nonzero float edges of opposite signs are a miss whatever the others.
// Why no ray slips between triangles: nonzero float signs are exact for one set of sheared vertex positions, shared by
// every triangle; a ray exactly on one edge line (zero) lies between the two triangles beside that edge, and either
// decision puts it in one of them; a ray on two edge lines is at their common vertex, where every edge through it is
// zero and all are decided in the one double frame. (Recomputing all three edges when one is zero, as before, could
// decide an edge in double in one triangle and in float in its neighbour.)
// Triangles whose sheared coordinates leave [2^-40, 2^40] are first scaled by an exact power of two, so huge and
// tiny scenes neither overflow nor underflow (results in the normal range are unchanged, bit for bit).
// A hit counts only when its computed t exceeds t_min by more than the rounding error bound of t (Pharr, Jakob,
// Humphreys, "Physically Based Rendering", 3rd ed., section 3.9.6): t near t_min cannot be told from rounding, and
// without the bound a ray leaving a surface could "hit" the plane it left at a small positive t that box culling
// (exactly conservative) rules out, so structures would disagree with brute force on secondary rays.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>

#include "rayaccel/core/float_rounding.h"
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

/// Bound on the rounding error of the t the watertight test computes from sheared triangle `s` with edge functions
/// eu, ev, ew and 1 / det = inv_det (pbrt-v3 section 3.9.6, whose error terms count at least the operations made
/// here). In the units of `s`: multiply by the same t_unscale as t.
inline float t_error_bound(const PreparedRay& r, const ShearedTriangle& s, float eu, float ev, float ew,
                           float inv_det) {
  const float max_z = fmax_inline(std::fabs(s.az), fmax_inline(std::fabs(s.bz), std::fabs(s.cz)));
  const float max_zt = std::fabs(r.shear_z) * max_z;
  const float max_xt = fmax_inline(std::fabs(s.ax), fmax_inline(std::fabs(s.bx), std::fabs(s.cx)));
  const float max_yt = fmax_inline(std::fabs(s.ay), fmax_inline(std::fabs(s.by), std::fabs(s.cy)));
  const float delta_z = float_gamma(3) * max_zt;
  const float delta_x = float_gamma(5) * (max_xt + max_zt);
  const float delta_y = float_gamma(5) * (max_yt + max_zt);
  const float delta_e = 2.0f * (float_gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
  const float max_e = fmax_inline(std::fabs(eu), fmax_inline(std::fabs(ev), std::fabs(ew)));
  return 3.0f * (float_gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * std::fabs(inv_det);
}

/// True when a hit at computed distance t (in the units of `s`, before t_unscale) lies beyond t_min by more than its
/// error bound, so that exactly t > t_min.
inline bool clears_t_min(const PreparedRay& r, const ShearedTriangle& s, float eu, float ev, float ew, float inv_det,
                         float t, float t_unscale) {
  return t > r.t_min + t_error_bound(r, s, eu, ev, ew, inv_det) * t_unscale;
}

/// An edge function computed exactly in double, as a float of the same sign: a nonzero value too small for float
/// becomes the smallest subnormal of its sign instead of a zero (which would put the ray on the edge).
inline float edge_to_float(double e) {
  const auto f = static_cast<float>(e);
  if (f != 0.0f || e == 0.0) return f;
  return e > 0.0 ? std::numeric_limits<float>::denorm_min() : -std::numeric_limits<float>::denorm_min();
}

/// The edge functions (u, v, w: opposite vertex 0, 1, 2) of triangle (v0, v1, v2) for ray r, with the origin offsets
/// and the shear computed in double from the float inputs: the float kernel's ray (its shear constants), without the
/// rounding and underflow of the float coordinates. Each vertex's coordinates are computed the same way in every
/// triangle that shares it, so a shared edge still gives exactly negated values (watertight).
inline std::array<double, 3> edge_functions_in_double(const PreparedRay& r, const Vec3& v0, const Vec3& v1,
                                                      const Vec3& v2) {
  double x[3], y[3];
  const Vec3* vertices[3] = {&v0, &v1, &v2};
  for (int i = 0; i < 3; ++i) {
    const Vec3& v = *vertices[i];
    const double z = double(v[r.kz]) - double(r.origin[r.kz]);
    x[i] = (double(v[r.kx]) - double(r.origin[r.kx])) - double(r.shear_x) * z;
    y[i] = (double(v[r.ky]) - double(r.origin[r.ky])) - double(r.shear_y) * z;
  }
  return {x[2] * y[1] - y[2] * x[1], x[0] * y[2] - y[0] * x[2], x[1] * y[0] - y[1] * x[0]};
}

/// The triangle in world space, for edges that float cannot decide, and the factor (a power of two squared) that
/// brings its double edge functions to the scale of the sheared float triangle.
struct TriangleForEdges {
  const Vec3& v0;
  const Vec3& v1;
  const Vec3& v2;
  double edge_scale = 1.0;
};

/// The three edge functions of a sheared triangle in float (u, v, w: opposite vertex a, b, c).
struct EdgeFunctions {
  float u, v, w;
  explicit EdgeFunctions(const ShearedTriangle& s)
      : u(s.cx * s.by - s.cy * s.bx), v(s.ax * s.cy - s.ay * s.cx), w(s.bx * s.ay - s.by * s.ax) {}
  /// Some edge function below zero and another above it (NaN counts as neither): the ray misses.
  bool mixed_signs() const { return (u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f); }
};

/// Sign test and distance of a sheared triangle whose float edge functions `e` (of `s`) are not of opposite signs;
/// `t_unscale` undoes a power-of-two scaling of it.
inline bool intersect_sheared_triangle(const PreparedRay& r, const ShearedTriangle& s, EdgeFunctions e, float t_unscale,
                                       const TriangleForEdges& world, std::uint32_t prim_id, Hit& hit) {
  if (e.u == 0.0f || e.v == 0.0f || e.w == 0.0f) {
    // On an edge in single precision: decide that edge (only that one) in double, from the vertices (the float
    // sheared coordinates may have rounded or underflowed: a ray 1e-45 from an edge near 0), without letting the
    // conversion back to float round a nonzero value to zero.
    const std::array<double, 3> exact = edge_functions_in_double(r, world.v0, world.v1, world.v2);
    if (e.u == 0.0f) e.u = edge_to_float(exact[0] * world.edge_scale);
    if (e.v == 0.0f) e.v = edge_to_float(exact[1] * world.edge_scale);
    if (e.w == 0.0f) e.w = edge_to_float(exact[2] * world.edge_scale);
    if (e.mixed_signs()) return false;
  }
  const float eu = e.u, ev = e.v, ew = e.w;
  const float det = eu + ev + ew;
  if (det == 0.0f) return false;
  const float az = r.shear_z * s.az;
  const float bz = r.shear_z * s.bz;
  const float cz = r.shear_z * s.cz;
  const float scaled_t = eu * az + ev * bz + ew * cz;
  const float inv_det = 1.0f / det;
  const float t = scaled_t * inv_det * t_unscale;
  if (!(t > r.t_min && t < hit.t)) return false;
  if (!clears_t_min(r, s, eu, ev, ew, inv_det, t, t_unscale)) return false;
  hit.t = t;
  hit.prim_id = prim_id;
  hit.u = ev * inv_det;
  hit.v = ew * inv_det;
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
  if (e.mixed_signs()) return false;
  const TriangleForEdges scaled{world.v0, world.v1, world.v2, std::ldexp(1.0, -2 * exponent)};
  return intersect_sheared_triangle(r, s, e, std::ldexp(1.0f, exponent), scaled, prim_id, hit);
}

/// Tests triangle (v0, v1, v2) and, when it is hit with r.t_min < t < hit.t (t clearing t_min by its error bound),
/// stores t, prim_id and the Embree-style barycentrics (p = (1-u-v)*v0 + u*v1 + v*v2) in hit and returns true.
/// Triangles with NaN vertices are never hit. Requires -ffp-contract=off (see cmake/Warnings.cmake).
inline bool intersect_triangle(const PreparedRay& r, const Vec3& v0, const Vec3& v1, const Vec3& v2,
                               std::uint32_t prim_id, Hit& hit) {
  const Vec3 a = v0 - r.origin;
  const Vec3 b = v1 - r.origin;
  const Vec3 c = v2 - r.origin;
  const ShearedTriangle s{a[r.kx] - r.shear_x * a[r.kz], a[r.ky] - r.shear_y * a[r.kz], a[r.kz],
                          b[r.kx] - r.shear_x * b[r.kz], b[r.ky] - r.shear_y * b[r.kz], b[r.kz],
                          c[r.kx] - r.shear_x * c[r.kz], c[r.ky] - r.shear_y * c[r.kz], c[r.kz]};
  // Float edge functions of opposite signs are a miss in any range: overflow keeps the sign (inf - finite), and
  // underflow can only turn a sign into zero. The rest is decided in the safe range, rescaled if need be.
  const EdgeFunctions e(s);
  if (e.mixed_signs()) return false;
  const TriangleForEdges world{v0, v1, v2};
  if (in_safe_range(s)) return intersect_sheared_triangle(r, s, e, 1.0f, world, prim_id, hit);
  return intersect_rescaled_triangle(r, s, world, prim_id, hit);
}

}  // namespace rayaccel
