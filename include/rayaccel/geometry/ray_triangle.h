// Watertight ray/triangle intersection (Woop, Benthin, Wald 2013, "Watertight Ray/Triangle Intersection", JCGT 2(1)).
// Edge functions are computed in a ray-sheared space; a shared edge yields exactly negated values in its two
// triangles, so a ray through an edge or vertex of a closed mesh hits at least one triangle. No back-face culling.
#pragma once

#include <cstdint>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/core/vec3.h"

namespace rayaccel {

/// Tests triangle (v0, v1, v2) and, when it is hit with r.t_min < t < hit.t, stores t, prim_id and the Embree-style
/// barycentrics (p = (1-u-v)*v0 + u*v1 + v*v2) in hit and returns true. Degenerate (zero-area) triangles and
/// triangles with NaN vertices are never hit. Requires -ffp-contract=off (see cmake/Warnings.cmake).
inline bool intersect_triangle(const PreparedRay& r, const Vec3& v0, const Vec3& v1, const Vec3& v2,
                               std::uint32_t prim_id, Hit& hit) {
  const Vec3 a = v0 - r.origin;
  const Vec3 b = v1 - r.origin;
  const Vec3 c = v2 - r.origin;
  const float ax = a[r.kx] - r.shear_x * a[r.kz];
  const float ay = a[r.ky] - r.shear_y * a[r.kz];
  const float bx = b[r.kx] - r.shear_x * b[r.kz];
  const float by = b[r.ky] - r.shear_y * b[r.kz];
  const float cx = c[r.kx] - r.shear_x * c[r.kz];
  const float cy = c[r.ky] - r.shear_y * c[r.kz];
  float eu = cx * by - cy * bx;
  float ev = ax * cy - ay * cx;
  float ew = bx * ay - by * ax;
  if (eu == 0.0f || ev == 0.0f || ew == 0.0f) {
    // On an edge in single precision: decide in double, where these products are exact.
    eu = static_cast<float>(double(cx) * double(by) - double(cy) * double(bx));
    ev = static_cast<float>(double(ax) * double(cy) - double(ay) * double(cx));
    ew = static_cast<float>(double(bx) * double(ay) - double(by) * double(ax));
  }
  if ((eu < 0.0f || ev < 0.0f || ew < 0.0f) && (eu > 0.0f || ev > 0.0f || ew > 0.0f)) return false;
  const float det = eu + ev + ew;
  if (det == 0.0f) return false;
  const float az = r.shear_z * a[r.kz];
  const float bz = r.shear_z * b[r.kz];
  const float cz = r.shear_z * c[r.kz];
  const float scaled_t = eu * az + ev * bz + ew * cz;
  const float inv_det = 1.0f / det;
  const float t = scaled_t * inv_det;
  if (!(t > r.t_min && t < hit.t)) return false;
  hit.t = t;
  hit.prim_id = prim_id;
  hit.u = ev * inv_det;
  hit.v = ew * inv_det;
  return true;
}

}  // namespace rayaccel
