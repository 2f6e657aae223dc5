// Sutherland-Hodgman clipping of a triangle to a box, for spatial splits (Stich, Friedrich, Dietrich 2009).
#include "rayaccel/bvh/clip_polygon.h"

#include <cmath>

namespace rayaccel {

namespace {

/// Keeps the part of polygon `in` with sign * (p[axis] - plane) <= 0.
int clip_to_plane(const Vec3* in, int n, int axis, float plane, float sign, Vec3* out) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3& p = in[i];
    const Vec3& q = in[(i + 1) % n];
    const float dp = sign * (p[axis] - plane);
    const float dq = sign * (q[axis] - plane);
    if (dp <= 0.0f) out[m++] = p;
    if ((dp < 0.0f && dq > 0.0f) || (dp > 0.0f && dq < 0.0f)) {
      const float t = dp / (dp - dq);
      Vec3 x = p + (q - p) * t;
      x[axis] = plane;
      out[m++] = x;
    }
  }
  return m;
}

}  // namespace

int clip_triangle_to_box(const Vec3& a, const Vec3& b, const Vec3& c, const AABB& box, ClippedPolygon& out) {
  ClippedPolygon scratch;
  out[0] = a;
  out[1] = b;
  out[2] = c;
  int n = 3;
  for (int axis = 0; axis < 3 && n > 0; ++axis) {
    n = clip_to_plane(out.data(), n, axis, box.lo[axis], -1.0f, scratch.data());
    n = n > 0 ? clip_to_plane(scratch.data(), n, axis, box.hi[axis], 1.0f, out.data()) : 0;
  }
  return n;
}

AABB pad_for_rounding(const AABB& box) {
  const float magnitude = max_component(max(abs(box.lo), abs(box.hi)));
  const Vec3 pad{magnitude * 0x1p-20f + std::numeric_limits<float>::min()};
  return {box.lo - pad, box.hi + pad};
}

AABB clipped_triangle_bounds(const Vec3& a, const Vec3& b, const Vec3& c, const AABB& box) {
  ClippedPolygon poly;
  const int n = clip_triangle_to_box(a, b, c, pad_for_rounding(box), poly);
  AABB bounds;
  for (int i = 0; i < n; ++i) bounds.extend(poly[i]);
  if (bounds.is_empty()) return bounds;
  return intersection(bounds, box);
}

}  // namespace rayaccel
