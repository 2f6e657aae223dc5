// Clipping a triangle to an axis-aligned box (Sutherland & Hodgman 1974), used by the spatial-split builder (Stich,
// Friedrich, Dietrich 2009) to bound the part of a triangle on each side of a split plane.
#pragma once

#include <array>

#include "rayaccel/core/aabb.h"

namespace rayaccel {

/// Most vertices of a triangle clipped by the six planes of a box.
inline constexpr int kClippedPolygonMaxVertices = 9;
using ClippedPolygon = std::array<Vec3, kClippedPolygonMaxVertices>;

/// Clips triangle (a, b, c) to the closed box; writes the polygon to `out` and returns its vertex count (0 when the
/// triangle misses the box). Vertices on a clip plane get that plane's coordinate exactly; other coordinates carry
/// float rounding.
int clip_triangle_to_box(const Vec3& a, const Vec3& b, const Vec3& c, const AABB& box, ClippedPolygon& out);

/// Bounds of the part of triangle (a, b, c) inside `box`, padded by `pad` against rounding and then cut to `box`;
/// empty when the triangle misses the box.
AABB clipped_triangle_bounds(const Vec3& a, const Vec3& b, const Vec3& c, const AABB& box);

/// A box grown on every side by a few ulps of its largest coordinate magnitude, so clipping against it keeps every
/// point of the original box despite rounding.
AABB pad_for_rounding(const AABB& box);

}  // namespace rayaccel
