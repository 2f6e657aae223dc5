// Ray/capsule interval in double: the infinite cylinder's entry and exit, replaced by an end sphere's beyond the
// segment's ends; the cylinder quadratic in the cancellation-free form of ray_sphere.h (Ray Tracing Gems 2019).
#pragma once

#include <cmath>
#include <limits>
#include <utility>

#include "rayaccel/core/ray.h"
#include "rayaccel/geometry/ray_sphere.h"

namespace rayaccel {

/// The parameter interval [t0, t1] where the ray's line lies within `radius` of the segment [a, b], in double
/// precision; false when the line misses (or the ray has a NaN component). The ray's t range is not applied. a == b
/// is a sphere. The radius is a double so that callers may widen a float radius without rounding in float.
inline bool ray_capsule_interval(const PreparedRay& r, const Vec3& a, const Vec3& b, double radius, double& t0,
                                 double& t1) {
  const double ux = double(b.x) - a.x, uy = double(b.y) - a.y, uz = double(b.z) - a.z;
  const double uu = ux * ux + uy * uy + uz * uz;
  if (uu == 0.0) return ray_sphere_interval(r, a, radius, t0, t1);
  const double fx = double(r.origin.x) - a.x, fy = double(r.origin.y) - a.y, fz = double(r.origin.z) - a.z;
  const double dx = r.direction.x, dy = r.direction.y, dz = r.direction.z;
  const double fu = fx * ux + fy * uy + fz * uz, du = dx * ux + dy * uy + dz * uz;
  // The origin and direction without their components along the axis: the cylinder is |fp + t dp| <= radius.
  const double sf = fu / uu, sd = du / uu;
  const double px = fx - sf * ux, py = fy - sf * uy, pz = fz - sf * uz;
  const double qx = dx - sd * ux, qy = dy - sd * uy, qz = dz - sd * uz;
  const double qq = qx * qx + qy * qy + qz * qz;
  const double rr = radius * radius;
  const double pp = px * px + py * py + pz * pz;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double c0, c1;
  if (qq == 0.0) {
    // Parallel to the axis: inside the cylinder for every t or for none.
    if (!(pp <= rr)) return false;
    c0 = -kInf;
    c1 = kInf;
  } else {
    const double h = -(px * qx + py * qy + pz * qz);  // half of the usual b, negated
    const double s = h / qq;
    const double lx = px + s * qx, ly = py + s * qy, lz = pz + s * qz;
    const double disc = qq * (rr - (lx * lx + ly * ly + lz * lz));
    if (!(disc >= 0.0)) return false;
    const double q = h + std::copysign(std::sqrt(disc), h);
    c0 = (pp - rr) / q;
    c1 = q / qq;
    if (q == 0.0) c0 = c1 = 0.0;
    if (c0 > c1) std::swap(c0, c1);
  }
  // Axial coordinate of the line at t: 0 at a, 1 at b (NaN for t = +-inf with du = 0, i.e. never beyond an end).
  const auto axial = [&](double t) { return sf + t * sd; };
  const double y0 = axial(c0), y1 = axial(c1);
  t0 = c0;
  t1 = c1;
  double e0, e1;
  if (y0 < 0.0 || y0 > 1.0) {
    if (!ray_sphere_interval(r, y0 < 0.0 ? a : b, radius, e0, e1)) return false;
    t0 = e0;
  }
  if (y1 < 0.0 || y1 > 1.0) {
    if (!ray_sphere_interval(r, y1 < 0.0 ? a : b, radius, e0, e1)) return false;
    t1 = e1;
  }
  return t0 <= t1;
}

}  // namespace rayaccel
