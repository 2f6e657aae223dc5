// Exact triangle/box overlap by the separating-axis theorem (Akenine-Moller 2001, "Fast 3D Triangle-Box Overlap
// Testing"): the box's 3 face normals, the triangle's normal and the 9 edge/axis cross products. Evaluated in double
// precision relative to the box center, so float inputs are classified far more finely than any cell padding.
#pragma once

#include <algorithm>
#include <cmath>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/vec3.h"

namespace rayaccel {

namespace detail {
struct DVec3 {
  double x, y, z;
  double operator[](int a) const { return a == 0 ? x : (a == 1 ? y : z); }
};
inline DVec3 dsub(const DVec3& a, const DVec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline DVec3 dcross(const DVec3& a, const DVec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double ddot(const DVec3& a, const DVec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
}  // namespace detail

/// True when the closed triangle (a, b, c) and the closed box share a point (touching counts). Zero-area triangles
/// (segments, points) are handled: their degenerate axes are zero vectors and separate nothing. An empty box
/// overlaps nothing.
inline bool triangle_overlaps_box(const Vec3& a, const Vec3& b, const Vec3& c, const AABB& box) {
  using detail::DVec3;
  if (box.is_empty()) return false;
  const DVec3 center{0.5 * (double(box.lo.x) + box.hi.x), 0.5 * (double(box.lo.y) + box.hi.y),
                     0.5 * (double(box.lo.z) + box.hi.z)};
  const DVec3 half{0.5 * (double(box.hi.x) - box.lo.x), 0.5 * (double(box.hi.y) - box.lo.y),
                   0.5 * (double(box.hi.z) - box.lo.z)};
  const DVec3 v[3] = {detail::dsub({a.x, a.y, a.z}, center), detail::dsub({b.x, b.y, b.z}, center),
                      detail::dsub({c.x, c.y, c.z}, center)};
  // Box face normals: the triangle's bounds against the box.
  for (int axis = 0; axis < 3; ++axis) {
    const double lo = std::min({v[0][axis], v[1][axis], v[2][axis]});
    const double hi = std::max({v[0][axis], v[1][axis], v[2][axis]});
    if (lo > half[axis] || hi < -half[axis]) return false;
  }
  // Projection of the box onto `axis` is [-r, r]; the triangle's is [min p, max p].
  const auto separated = [&](const DVec3& axis) {
    const double p0 = detail::ddot(axis, v[0]), p1 = detail::ddot(axis, v[1]), p2 = detail::ddot(axis, v[2]);
    const double r = half.x * std::fabs(axis.x) + half.y * std::fabs(axis.y) + half.z * std::fabs(axis.z);
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
  };
  const DVec3 edges[3] = {detail::dsub(v[1], v[0]), detail::dsub(v[2], v[1]), detail::dsub(v[0], v[2])};
  if (separated(detail::dcross(edges[0], edges[1]))) return false;
  const DVec3 units[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const DVec3& e : edges) {
    for (const DVec3& u : units) {
      if (separated(detail::dcross(u, e))) return false;
    }
  }
  return true;
}

}  // namespace rayaccel
