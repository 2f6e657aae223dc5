// Sutherland–Hodgman clipping of a convex polygon against a half-space or an axis-aligned box (Sutherland & Hodgman
// 1974): the one copy of polygon clipping, used for the kd-tree's "perfect splits" (Wald & Havran 2006) and for
// the BSP tree's convex cells (Ize, Wald & Parker 2008).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/vec3.h"

namespace rayaccel {

/// Room a clip of an n-gon needs: a convex polygon gains at most one vertex, but clipped vertices are rounded to
/// float, so a polygon clipped before may be very slightly non-convex and cross a plane more than twice; each input
/// vertex still yields at most two output vertices. (n + 1 overflowed the BSP tree's buffers on the conference room.)
inline constexpr std::size_t clip_capacity(std::size_t n) { return 2 * n; }

/// The Sutherland-Hodgman step over in[0..n): keeps each vertex with distance(p) <= 0 and, where an edge's signed
/// distances have strictly opposite signs, its crossing point (interpolated in double, then passed through
/// on_crossing, which may snap it). Writes at most clip_capacity(n) vertices to `out` (n + 1 when the polygon is
/// exactly convex; `in` and `out` must not alias); returns their count.
template <class Distance, class OnCrossing>
inline int clip_polygon_by(const Vec3* in, int n, const Distance& distance, const OnCrossing& on_crossing, Vec3* out) {
  int count = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3& a = in[i];
    const Vec3& b = in[(i + 1) % n];
    const double da = distance(a), db = distance(b);
    if (da <= 0.0) out[count++] = a;
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) {
      const double s = da / (da - db);
      Vec3 p{float(a.x + s * (double(b.x) - a.x)), float(a.y + s * (double(b.y) - a.y)),
             float(a.z + s * (double(b.z) - a.z))};
      on_crossing(p);
      out[count++] = p;
    }
  }
  return count;
}

/// Keeps the part of the convex polygon in[0..n) where dot(normal, p) <= offset (points on the plane are kept) and
/// writes it to `out`, which must have room for clip_capacity(n) vertices. Returns the vertex count of the result (0 when
/// nothing is left). Signed distances and crossing points are computed in double; `in` and `out` must not alias.
inline int clip_polygon_to_halfspace(const Vec3* in, int n, const Vec3& normal, double offset, Vec3* out) {
  const auto distance = [&](const Vec3& p) {
    return double(normal.x) * p.x + double(normal.y) * p.y + double(normal.z) * p.z - offset;
  };
  return clip_polygon_by(in, n, distance, [](Vec3&) {}, out);
}

/// Keeps the part of the convex polygon in[0..n) on one side of the plane p[axis] == position: below (p[axis] <=
/// position) when keep_below, else above. Crossing points get exactly `position` on `axis`. `out` needs room for
/// n + 1 vertices; `in` and `out` must not alias. Returns the vertex count of the result.
inline int clip_polygon_to_axis_plane(const Vec3* in, int n, int axis, float position, bool keep_below, Vec3* out) {
  const auto distance = [&](const Vec3& p) {
    const double d = double(p[axis]) - position;
    return keep_below ? d : -d;
  };
  return clip_polygon_by(in, n, distance, [&](Vec3& p) { p[axis] = position; }, out);
}

/// Box widened on every side by a small relative margin (2^-20 of the largest coordinate magnitude per axis, plus
/// the smallest normal float), so that clipping against it never loses a part that touches the exact box.
inline AABB widen_for_clipping(const AABB& box) {
  AABB out = box;
  for (int a = 0; a < 3; ++a) {
    const float pad = std::fmax(std::fabs(box.lo[a]), std::fabs(box.hi[a])) * 0x1p-20f + 0x1p-126f;
    out.lo[a] = box.lo[a] - pad;
    out.hi[a] = box.hi[a] + pad;
  }
  return out;
}

/// Room for a triangle clipped by a box's six planes (9 vertices) plus the one spare a clip step needs.
using ClippedPolygon = std::array<Vec3, 10>;

/// Clips triangle (a, b, c) to `box` widened by widen_for_clipping() and returns the vertex count of the polygon left
/// in `out` (0 when the triangle misses the box): the points a volume is fitted to for one SBVH reference, and the
/// part whose bounds clip_triangle_to_box() takes.
inline int clip_triangle_polygon(const std::array<Vec3, 3>& triangle, const AABB& box, ClippedPolygon& out) {
  const AABB clip_box = widen_for_clipping(box);
  ClippedPolygon scratch;
  Vec3* current = out.data();
  Vec3* other = scratch.data();
  current[0] = triangle[0];
  current[1] = triangle[1];
  current[2] = triangle[2];
  int n = 3;
  for (int axis = 0; axis < 3 && n > 0; ++axis) {
    // A plane with every vertex on its kept side leaves the polygon as it is: skip it (same result, less work).
    // Clipping at lo moves no vertex above hi, so both tests can be made before either clip.
    bool above_lo = true, below_hi = true;
    for (int i = 0; i < n; ++i) {
      above_lo &= current[i][axis] >= clip_box.lo[axis];
      below_hi &= current[i][axis] <= clip_box.hi[axis];
    }
    if (!above_lo) {
      n = clip_polygon_to_axis_plane(current, n, axis, clip_box.lo[axis], false, other);
      std::swap(current, other);
      if (n == 0) break;
    }
    if (!below_hi) {
      n = clip_polygon_to_axis_plane(current, n, axis, clip_box.hi[axis], true, other);
      std::swap(current, other);
    }
  }
  if (current != out.data()) std::copy(current, current + n, out.data());
  return n;
}

/// Bounds of the part of triangle (a, b, c) inside `box`, conservative: the triangle is clipped against the box
/// widened by widen_for_clipping(), and the bounds of what is left are intersected with `box`. Empty when the
/// triangle does not reach the box. A triangle that only touches the box yields a flat (non-empty) result.
inline AABB clip_triangle_to_box(const Vec3& a, const Vec3& b, const Vec3& c, const AABB& box) {
  ClippedPolygon polygon;
  const int n = clip_triangle_polygon({a, b, c}, box, polygon);
  AABB bounds;
  for (int i = 0; i < n; ++i) bounds.extend(polygon[i]);
  bounds = intersection(bounds, box);
  return bounds.is_empty() ? AABB{} : bounds;
}

/// Area of a planar polygon p[0..n) (half the length of the summed edge cross products, in double); 0 for n < 3.
inline double polygon_area(const Vec3* p, int n) {
  double sx = 0.0, sy = 0.0, sz = 0.0;
  for (int i = 1; i + 1 < n; ++i) {
    const double ux = double(p[i].x) - p[0].x, uy = double(p[i].y) - p[0].y, uz = double(p[i].z) - p[0].z;
    const double vx = double(p[i + 1].x) - p[0].x, vy = double(p[i + 1].y) - p[0].y,
                 vz = double(p[i + 1].z) - p[0].z;
    sx += uy * vz - uz * vy;
    sy += uz * vx - ux * vz;
    sz += ux * vy - uy * vx;
  }
  return 0.5 * std::sqrt(sx * sx + sy * sy + sz * sz);
}

}  // namespace rayaccel
