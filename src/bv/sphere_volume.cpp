// Bounding-sphere fitting: Welzl's move-to-front minimum sphere (Welzl 1991, "Smallest enclosing disks (balls and
// ellipsoids)"; Gaertner 1999 for the move-to-front form) for small sets, and Larsson's EPOS-26 (SIGRAD 2008) for
// large ones: the exact sphere of 26 extremal points, grown by Ritter's pass (Ritter 1990, Graphics Gems).
#include "rayaccel/bv/sphere_volume.h"

#include <algorithm>
#include <vector>

#include "fit_support.h"
#include "rayaccel/core/float_rounding.h"

namespace rayaccel {
namespace {

using bv_detail::Vec3d;

struct Ball {
  Vec3d center;
  double radius2 = -1.0;  // squared radius; negative = empty
  bool contains(const Vec3d& p) const {
    // A relative tolerance keeps support points, which lie on the sphere up to rounding, from re-entering.
    return bv_detail::length_squared(p - center) <= radius2 * (1.0 + 1e-10);
  }
};

Ball ball_through_two(const Vec3d& a, const Vec3d& b) {
  const Vec3d c = (a + b) * 0.5;
  return {c, bv_detail::length_squared(a - c)};
}

Ball smallest_containing(std::span<const Ball> candidates, std::span<const Vec3d> points);

/// Circumscribed circle of a triangle; the farthest pair's ball when the three points are (nearly) collinear.
Ball ball_through_three(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const Vec3d ab = b - a, ac = c - a;
  const Vec3d n = bv_detail::cross(ab, ac);
  const double n2 = bv_detail::length_squared(n);
  if (n2 <= 1e-20 * bv_detail::length_squared(ab) * bv_detail::length_squared(ac)) {
    const Ball pairs[3] = {ball_through_two(a, b), ball_through_two(a, c), ball_through_two(b, c)};
    const Vec3d pts[3] = {a, b, c};
    return smallest_containing(pairs, pts);
  }
  const Vec3d offset = (bv_detail::cross(n, ab) * bv_detail::length_squared(ac) +
                        bv_detail::cross(ac, n) * bv_detail::length_squared(ab)) *
                       (1.0 / (2.0 * n2));
  return {a + offset, bv_detail::length_squared(offset)};
}

/// Circumscribed sphere of a tetrahedron; for a (nearly) flat one, the smallest sphere through fewer of its points
/// that contains all four.
Ball ball_through_four(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& d) {
  const Vec3d ab = b - a, ac = c - a, ad = d - a;
  const double det = bv_detail::dot(ab, bv_detail::cross(ac, ad));
  const double scale = bv_detail::length(ab) * bv_detail::length(ac) * bv_detail::length(ad);
  if (std::fabs(det) <= 1e-10 * scale) {
    const Ball subsets[10] = {ball_through_two(a, b),       ball_through_two(a, c),       ball_through_two(a, d),
                              ball_through_two(b, c),       ball_through_two(b, d),       ball_through_two(c, d),
                              ball_through_three(a, b, c),  ball_through_three(a, b, d),  ball_through_three(a, c, d),
                              ball_through_three(b, c, d)};
    const Vec3d pts[4] = {a, b, c, d};
    return smallest_containing(subsets, pts);
  }
  const Vec3d offset = (bv_detail::cross(ac, ad) * bv_detail::length_squared(ab) +
                        bv_detail::cross(ad, ab) * bv_detail::length_squared(ac) +
                        bv_detail::cross(ab, ac) * bv_detail::length_squared(ad)) *
                       (1.0 / (2.0 * det));
  return {a + offset, bv_detail::length_squared(offset)};
}

/// The smallest candidate containing every point; the largest candidate when none does (rounding only).
Ball smallest_containing(std::span<const Ball> candidates, std::span<const Vec3d> points) {
  const Ball* best = nullptr;
  const Ball* largest = &candidates[0];
  for (const Ball& b : candidates) {
    if (b.radius2 > largest->radius2) largest = &b;
    const bool all = std::all_of(points.begin(), points.end(), [&](const Vec3d& p) { return b.contains(p); });
    if (all && (!best || b.radius2 < best->radius2)) best = &b;
  }
  return best ? *best : *largest;
}

Ball ball_of_support(const Vec3d* support, int count) {
  switch (count) {
    case 0: return {};
    case 1: return {support[0], 0.0};
    case 2: return ball_through_two(support[0], support[1]);
    case 3: return ball_through_three(support[0], support[1], support[2]);
    default: return ball_through_four(support[0], support[1], support[2], support[3]);
  }
}

/// Welzl's algorithm with move-to-front: the smallest ball containing points[0, end) with support[0, count) on its
/// boundary. Reorders points.
Ball welzl(std::vector<Vec3d>& points, std::size_t end, Vec3d* support, int count) {
  Ball ball = ball_of_support(support, count);
  if (count == 4) return ball;
  for (std::size_t i = 0; i < end; ++i) {
    if (ball.radius2 >= 0.0 && ball.contains(points[i])) continue;
    support[count] = points[i];
    ball = welzl(points, i, support, count + 1);
    std::rotate(points.begin(), points.begin() + i, points.begin() + i + 1);
  }
  return ball;
}

Ball exact_ball(std::vector<Vec3d> points) {
  Vec3d support[4];
  return welzl(points, points.size(), support, 0);
}

/// EPOS-26: the exact ball of the extremal points on the 13 k-DOP-26 directions, then Ritter's growth pass.
Ball epos26_ball(std::span<const Vec3> points) {
  std::vector<Vec3d> extremal = bv_detail::distinct_points(points, bv_detail::extremal_points_26(points));
  Ball ball = exact_ball(std::move(extremal));
  double radius = std::sqrt(ball.radius2);
  for (const Vec3& pf : points) {
    const Vec3d p(pf);
    const double dist = bv_detail::length(p - ball.center);
    if (dist <= radius) continue;
    const double grown = 0.5 * (radius + dist);
    ball.center = ball.center + (p - ball.center) * ((grown - radius) / dist);
    radius = grown;
  }
  ball.radius2 = radius * radius;
  return ball;
}

}  // namespace

SphereVolume SphereVolume::fit(std::span<const Vec3> points) {
  SphereVolume v;
  if (points.empty()) return v;
  Ball ball;
  if (points.size() <= kExactFitMaxPoints) {
    std::vector<Vec3d> pts;
    pts.reserve(points.size());
    for (const Vec3& p : points) pts.emplace_back(p);
    ball = exact_ball(std::move(pts));
  } else {
    ball = epos26_ball(points);
  }
  // The stored center is a float; the radius is measured from it, so containment never depends on the fit's
  // rounding.
  v.center = bv_detail::to_float(ball.center);
  const Vec3d c(v.center);
  double radius2 = 0.0;
  for (const Vec3& p : points) radius2 = std::max(radius2, bv_detail::length_squared(Vec3d(p) - c));
  v.radius = round_up_to_float(std::sqrt(radius2));
  return v;
}

AABB SphereVolume::bounds() const {
  if (!(radius >= 0.0f)) return AABB::empty();
  AABB box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = round_down_to_float(double(center[a]) - radius);
    box.hi[a] = round_up_to_float(double(center[a]) + radius);
  }
  return box;
}

bool SphereVolume::contains(const Vec3& p) const {
  if (!(radius >= 0.0f)) return false;
  const double slack = 4.0 * 0x1p-24 * (double(max_component(abs(center))) + radius);
  const double limit = double(radius) + slack;
  return bv_detail::length_squared(Vec3d(p) - Vec3d(center)) <= limit * limit;
}

}  // namespace rayaccel
