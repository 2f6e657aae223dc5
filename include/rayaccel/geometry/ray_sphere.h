// Ray/sphere intersection, solved in double precision with the cancellation-free quadratic form
// (Haines et al., "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems, 2019).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/core/vec3.h"

namespace rayaccel {

/// The parameter interval [t0, t1] (t0 <= t1) where the ray's line lies inside the sphere (center, radius), in
/// double precision; false when the line misses (or the ray has a NaN component). The ray's t range is not applied.
/// The radius is a double so that callers may widen a float radius without rounding (or overflowing) in float.
inline bool ray_sphere_interval(const PreparedRay& r, const Vec3& center, double radius, double& t0, double& t1) {
  const double fx = double(r.origin.x) - center.x, fy = double(r.origin.y) - center.y,
               fz = double(r.origin.z) - center.z;
  const double dx = r.direction.x, dy = r.direction.y, dz = r.direction.z;
  const double a = dx * dx + dy * dy + dz * dz;
  const double b = -(fx * dx + fy * dy + fz * dz);  // half of the usual b, negated
  // Discriminant as rr - |f + (b/a) d|^2, which keeps its precision for distant rays.
  const double s = b / a;
  const double lx = fx + s * dx, ly = fy + s * dy, lz = fz + s * dz;
  const double rr = radius * radius;
  const double disc = a * (rr - (lx * lx + ly * ly + lz * lz));
  if (!(disc >= 0.0)) return false;
  const double c = fx * fx + fy * fy + fz * fz - rr;
  const double q = b + std::copysign(std::sqrt(disc), b);
  t0 = c / q;
  t1 = q / a;
  if (q == 0.0) t0 = t1 = 0.0;
  if (t0 > t1) std::swap(t0, t1);
  return true;
}

/// Tests the sphere (center, radius) and, when it is hit with r.t_min < t < hit.t, stores the nearer such t,
/// prim_id and (u, v) = (longitude / 2pi, latitude / pi) of the hit point in hit and returns true.
inline bool intersect_sphere(const PreparedRay& r, const Vec3& center, float radius, std::uint32_t prim_id, Hit& hit) {
  double t0, t1;
  if (!ray_sphere_interval(r, center, radius, t0, t1)) return false;
  float t = static_cast<float>(t0);
  if (!(t > r.t_min && t < hit.t)) {
    t = static_cast<float>(t1);
    if (!(t > r.t_min && t < hit.t)) return false;
  }
  hit.t = t;
  hit.prim_id = prim_id;
  const double fx = double(r.origin.x) - center.x, fy = double(r.origin.y) - center.y,
               fz = double(r.origin.z) - center.z;
  const double dx = r.direction.x, dy = r.direction.y, dz = r.direction.z;
  const double px = fx + t * dx, py = fy + t * dy, pz = fz + t * dz;
  const double phi = std::atan2(pz, px);
  const double cos_theta = std::clamp(py / radius, -1.0, 1.0);
  hit.u = static_cast<float>((phi < 0 ? phi + 2 * std::numbers::pi : phi) / (2 * std::numbers::pi));
  hit.v = static_cast<float>(std::acos(cos_theta) / std::numbers::pi);
  return true;
}

}  // namespace rayaccel
