// Closest point of a triangle to a point (Ericson 2005, 5.1.5: the Voronoi region from six dot products), computed
// in double from the float inputs so every structure gets the same distance, bit for bit.
#pragma once

#include "rayaccel/core/vec3.h"

namespace rayaccel {

/// The closest point of a triangle, with its Embree-style barycentrics (point = (1-u-v) v0 + u v1 + v v2).
struct TrianglePoint {
  double distance_squared = 0.0;
  double x = 0.0, y = 0.0, z = 0.0;  ///< the closest point
  double u = 0.0, v = 0.0;
};

/// Closest point of triangle (v0, v1, v2) to p. Inputs must be finite and the triangle of nonzero area (Scene's
/// valid triangles: a zero-area one could fall into the face case with a zero denominator).
inline TrianglePoint closest_point_on_triangle(const Vec3& p, const Vec3& v0, const Vec3& v1, const Vec3& v2) {
  struct D3 {
    double x, y, z;
  };
  const auto sub = [](const Vec3& a, const Vec3& b) { return D3{double(a.x) - b.x, double(a.y) - b.y, double(a.z) - b.z}; };
  const auto dot = [](const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; };
  const D3 ab = sub(v1, v0), ac = sub(v2, v0), ap = sub(p, v0);
  // (u, v): the barycentrics of the closest point, from the region it lies in.
  double u = 0.0, v = 0.0;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  const D3 bp = sub(p, v1);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  const D3 cp = sub(p, v2);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
  if (d1 <= 0.0 && d2 <= 0.0) {
    // vertex v0
  } else if (d3 >= 0.0 && d4 <= d3) {
    u = 1.0;  // vertex v1
  } else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    u = d1 / (d1 - d3);  // edge v0 v1
  } else if (d6 >= 0.0 && d5 <= d6) {
    v = 1.0;  // vertex v2
  } else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    v = d2 / (d2 - d6);  // edge v0 v2
  } else if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    v = (d4 - d3) / ((d4 - d3) + (d5 - d6));  // edge v1 v2
    u = 1.0 - v;
  } else {
    const double denominator = va + vb + vc;  // inside the face; > 0 here for a triangle of nonzero area
    u = vb / denominator;
    v = vc / denominator;
  }
  TrianglePoint out;
  out.u = u;
  out.v = v;
  out.x = v0.x + ab.x * u + ac.x * v;
  out.y = v0.y + ab.y * u + ac.y * v;
  out.z = v0.z + ab.z * u + ac.z * v;
  const D3 gap{p.x - out.x, p.y - out.y, p.z - out.z};
  out.distance_squared = dot(gap, gap);
  return out;
}

}  // namespace rayaccel
