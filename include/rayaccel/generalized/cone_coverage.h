// Analytic cone coverage (Amanatides 1984): the exact fraction of a cone's solid angle a triangle covers, from its
// projection cut by the cross-section disk edge by edge (flat pieces by Van Oosterom & Strackee's solid angle, arcs
// as cap sectors).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>

#include "rayaccel/generalized/cone.h"

namespace rayaccel::generalized {

/// A point of the projection plane, in the cone's frame (u, v) at unit distance along the axis.
struct PlanePoint {
  double x = 0.0, y = 0.0;
};

/// The z component of the cross product of two plane points (twice the signed area of the triangle they make with
/// the origin).
inline double cross2(const PlanePoint& p, const PlanePoint& q) { return p.x * q.y - p.y * q.x; }

/// Signed solid angle seen from the apex (at unit height above the origin of the plane) of the part of the triangle
/// (origin, p, q) inside the circle of radius tan(half_angle): positive when p -> q turns counter-clockwise. Summed
/// over a closed boundary it gives the solid angle of the enclosed region inside the cone.
double segment_solid_angle(const PlanePoint& p, const PlanePoint& q, double half_angle);

/// Solid angle seen from the apex (at unit height above the origin of the plane) of the part of the closed polygon
/// inside the circle of radius tan(half_angle) about the origin: exact up to rounding (a few ulps per edge). Either
/// orientation; a self-intersecting polygon gives the signed sum of its loops' parts. Fewer than 3 points -> 0.
double disk_polygon_solid_angle(std::span<const PlanePoint> polygon, double half_angle);

struct TriangleCoverage {
  /// The triangle clipped to the depth slab and projected (3 to 5 points), for ProjectedUnion (cone_union.h).
  std::array<PlanePoint, 16> polygon{};
  std::size_t count = 0;
  /// The fraction of the cone's solid angle whose rays meet the triangle, in [0, 1] (as if it were alone).
  double coverage = 0.0;
  /// Distance from the apex to the triangle along the direction of the centroid of its projection clipped to the
  /// square around the cone's disk (where it covers the cone; the depth that orders triangles front to back).
  float distance = 0.0f;
};

/// The triangle's coverage of the cone, or nullopt when it covers none of it (a zero-area overlap included). The
/// cone's distance range is taken as the slab t_min cos(half_angle) <= (p - apex) . axis <= t_max of depths along
/// the axis, which holds every point of the range (a point at distance s lies at depth s cos(b), b <= half_angle):
/// exact for t_min = 0 and t_max = inf, otherwise it may count a sliver of depth up to t_max (1 - cos(half_angle)).
std::optional<TriangleCoverage> triangle_coverage(const PreparedCone& cone, const Vec3& a, const Vec3& b,
                                                  const Vec3& c);

}  // namespace rayaccel::generalized
