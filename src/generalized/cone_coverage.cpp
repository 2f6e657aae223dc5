// Analytic cone coverage: a triangle clipped to the cone's depth slab, projected from the apex, and its solid angle
// inside the cone summed edge by edge (Van Oosterom & Strackee 1983 for flat pieces, cap sectors for arcs).
#include "rayaccel/generalized/cone_coverage.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace rayaccel::generalized {

namespace {

using detail::dcross;
using detail::ddot;
using detail::dsub;

double dot2(const PlanePoint& p, const PlanePoint& q) { return p.x * q.x + p.y * q.y; }

/// Signed solid angle of the triangle (origin, p, q) of the plane, where it lies inside the circle of radius r:
/// the segment pq is split where it crosses the circle; a piece inside is a flat triangle (its solid angle from
/// Van Oosterom & Strackee's formula with the apex one unit above the origin), a piece outside is replaced by the
/// arc it subtends (a sector of the cap: its azimuth times 1 - cos(half_angle)).
double edge_solid_angle(const PlanePoint& p, const PlanePoint& q, double r, double cap_height) {
  const PlanePoint d{q.x - p.x, q.y - p.y};
  const double a = dot2(d, d);
  if (a == 0.0) return 0.0;
  std::array<double, 4> ts{0.0, 0.0, 0.0, 1.0};
  int n = 1;
  const double b = dot2(p, d), c = dot2(p, p) - r * r;
  const double disc = b * b - a * c;
  if (disc > 0.0) {
    const double s = std::sqrt(disc);
    for (const double t : {(-b - s) / a, (-b + s) / a}) {
      if (t > 0.0 && t < 1.0) ts[std::size_t(n++)] = t;
    }
  }
  ts[std::size_t(n)] = 1.0;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double t0 = ts[std::size_t(i)], t1 = ts[std::size_t(i + 1)], tm = 0.5 * (t0 + t1);
    const PlanePoint e0{p.x + t0 * d.x, p.y + t0 * d.y}, e1{p.x + t1 * d.x, p.y + t1 * d.y};
    const PlanePoint mid{p.x + tm * d.x, p.y + tm * d.y};
    if (dot2(mid, mid) <= r * r) {
      const double r0 = std::sqrt(1.0 + dot2(e0, e0)), r1 = std::sqrt(1.0 + dot2(e1, e1));
      sum += 2.0 * std::atan2(cross2(e0, e1), r0 * r1 + r0 + r1 + dot2(e0, e1) + 1.0);
    } else {
      sum += std::atan2(cross2(e0, e1), dot2(e0, e1)) * cap_height;
    }
  }
  return sum;
}

/// 1 - cos(angle) without cancellation for small angles.
double cap_height(double angle) {
  const double s = std::sin(0.5 * angle);
  return 2.0 * s * s;
}

/// The polygon's point nearest the origin (the origin itself when inside).
PlanePoint nearest_to_origin(std::span<const PlanePoint> poly) {
  bool inside_pos = true, inside_neg = true;
  PlanePoint best{std::numeric_limits<double>::infinity(), 0.0};
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const PlanePoint& p = poly[i];
    const PlanePoint& q = poly[(i + 1) % poly.size()];
    const double side = cross2(p, q);
    inside_pos = inside_pos && side >= 0.0;
    inside_neg = inside_neg && side <= 0.0;
    const PlanePoint d{q.x - p.x, q.y - p.y};
    const double len = dot2(d, d);
    const double t = len > 0.0 ? std::clamp(-dot2(p, d) / len, 0.0, 1.0) : 0.0;
    const PlanePoint c{p.x + t * d.x, p.y + t * d.y};
    if (dot2(c, c) < dot2(best, best)) best = c;
  }
  return inside_pos || inside_neg ? PlanePoint{} : best;
}

/// The centroid of the convex polygon's part inside the square |x|, |y| <= r around the disk (a direction that
/// stands for where the triangle covers the cone, for ordering triangles by depth); nullopt when that part is empty.
std::optional<PlanePoint> centroid_in_square(std::span<const PlanePoint> poly, double r) {
  std::array<PlanePoint, 16> a{}, b{};
  std::size_t n = poly.size();
  std::copy(poly.begin(), poly.end(), a.begin());
  const double nx[4] = {1, -1, 0, 0}, ny[4] = {0, 0, 1, -1};
  for (int side = 0; side < 4 && n > 0; ++side) {
    std::size_t m = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const PlanePoint& p = a[i];
      const PlanePoint& q = a[(i + 1) % n];
      const double dp = r - (nx[side] * p.x + ny[side] * p.y), dq = r - (nx[side] * q.x + ny[side] * q.y);
      if (dp >= 0.0) b[m++] = p;
      if ((dp >= 0.0) != (dq >= 0.0)) {
        const double t = dp / (dp - dq);
        b[m++] = {p.x + (q.x - p.x) * t, p.y + (q.y - p.y) * t};
      }
    }
    a = b;
    n = m;
  }
  double area = 0.0, cx = 0.0, cy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const PlanePoint& p = a[i];
    const PlanePoint& q = a[(i + 1) % n];
    const double c = cross2(p, q);
    area += c;
    cx += (p.x + q.x) * c;
    cy += (p.y + q.y) * c;
  }
  if (!(std::fabs(area) > 0.0)) return std::nullopt;
  return PlanePoint{cx / (3.0 * area), cy / (3.0 * area)};
}

}  // namespace

double segment_solid_angle(const PlanePoint& p, const PlanePoint& q, double half_angle) {
  return edge_solid_angle(p, q, std::tan(half_angle), cap_height(half_angle));
}

double disk_polygon_solid_angle(std::span<const PlanePoint> polygon, double half_angle) {
  if (polygon.size() < 3) return 0.0;
  const double r = std::tan(half_angle), h = cap_height(half_angle);
  double sum = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    sum += edge_solid_angle(polygon[i], polygon[(i + 1) % polygon.size()], r, h);
  }
  return std::fabs(sum);
}

std::optional<TriangleCoverage> triangle_coverage(const PreparedCone& cone, const Vec3& a, const Vec3& b,
                                                  const Vec3& c) {
  const Cone& k = cone.cone();
  const auto local = [&](const Vec3& p) {
    const DVec3 d{double(p.x) - k.apex.x, double(p.y) - k.apex.y, double(p.z) - k.apex.z};
    return DVec3{ddot(d, cone.u()), ddot(d, cone.v()), ddot(d, cone.axis())};
  };
  const std::array<DVec3, 3> tri{local(a), local(b), local(c)};
  for (const DVec3& p : tri) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return std::nullopt;
  }
  for (const DVec3& p : tri) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return std::nullopt;
  }
  // The depth slab, the same for every triangle of the cone; its near side kept off the apex (by 1e-7 of the apex's
  // largest coordinate, at least 1e-7) so that the projection stays finite. Each crossing is computed from the same
  // endpoint whichever way an edge runs, so that an edge two triangles share is clipped to the same point in both
  // (ProjectedUnion relies on it).
  const double apex_scale = std::fmax(std::fmax(std::fabs(k.apex.x), std::fabs(k.apex.y)), std::fabs(k.apex.z));
  const double z_near =
      std::fmax(double(k.t_min) * std::cos(double(k.half_angle)), 1e-7 * std::fmax(apex_scale, 1.0));
  const double z_far = k.t_max;
  std::array<DVec3, 8> poly{tri[0], tri[1], tri[2]};
  std::size_t count = 3;
  const auto clip = [&](double plane, double sign) {
    std::array<DVec3, 8> out;
    std::size_t m = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const DVec3& p = poly[i];
      const DVec3& q = poly[(i + 1) % count];
      const double dp = sign * (p.z - plane), dq = sign * (q.z - plane);
      if (dp >= 0.0) out[m++] = p;
      if ((dp >= 0.0) != (dq >= 0.0)) {
        const bool from_p = p.z < q.z || (p.z == q.z && (p.x < q.x || (p.x == q.x && p.y < q.y)));
        const DVec3& f = from_p ? p : q;
        const DVec3& g = from_p ? q : p;
        const double df = from_p ? dp : dq, dg = from_p ? dq : dp;
        const double s = df / (df - dg);
        out[m++] = {f.x + (g.x - f.x) * s, f.y + (g.y - f.y) * s, f.z + (g.z - f.z) * s};
      }
    }
    poly = out;
    count = m;
  };
  clip(z_near, 1.0);
  if (std::isfinite(z_far) && count > 0) clip(z_far, -1.0);
  if (count < 3) return std::nullopt;
  std::array<PlanePoint, 16> plane;
  for (std::size_t i = 0; i < count; ++i) plane[i] = {poly[i].x / poly[i].z, poly[i].y / poly[i].z};
  const std::span<const PlanePoint> projected(plane.data(), count);
  const double total = 2.0 * std::numbers::pi * cap_height(k.half_angle);
  const double coverage = std::fmin(1.0, disk_polygon_solid_angle(projected, k.half_angle) / total);
  if (!(coverage > 1e-12)) return std::nullopt;
  // Distance along the direction of the centroid of where the triangle covers the cone's bounding square (else the
  // covered direction nearest the axis): where that direction meets the triangle's plane.
  const PlanePoint q =
      centroid_in_square(projected, std::tan(double(k.half_angle))).value_or(nearest_to_origin(projected));
  const DVec3 dir{q.x, q.y, 1.0};
  const DVec3 n = dcross(dsub(tri[1], tri[0]), dsub(tri[2], tri[0]));
  double distance = ddot(n, tri[0]) / ddot(n, dir) * dnorm(dir);
  if (!(distance >= 0.0) || !std::isfinite(distance)) {
    distance = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < count; ++i) distance = std::fmin(distance, dnorm(poly[i]));
  }
  return TriangleCoverage{plane, count, coverage, float(distance)};
}

}  // namespace rayaccel::generalized
