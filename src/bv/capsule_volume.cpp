// Capsule fitting: per candidate axis, the shortest segment for a few radii from the smallest up; the least surface
// area wins (the geometry of one axis below).
#include "rayaccel/bv/capsule_volume.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "fit_support.h"
#include "principal_axes.h"
#include "rayaccel/core/float_rounding.h"

namespace rayaccel {

namespace {

using bv_detail::Vec3d;

/// Radii tried per axis, as multiples of the smallest one (the largest distance from the axis line).
constexpr double kRadiusFactors[] = {1.0, 1.1, 1.25, 1.5, 2.0, 3.0};

struct Candidate {
  Vec3d a, b;
  double radius = 0.0;
  double area = std::numeric_limits<double>::infinity();
};

/// The least-area capsule on the axis direction u (unit).
Candidate fit_on_axis(std::span<const Vec3> points, const Vec3d& u) {
  const Vec3d helper = std::fabs(u.x) < 0.6 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
  const Vec3d v = bv_detail::normalize(bv_detail::cross(u, helper));
  const Vec3d w = bv_detail::cross(u, v);
  double lo_v = std::numeric_limits<double>::infinity(), hi_v = -lo_v, lo_w = lo_v, hi_w = -lo_v;
  for (const Vec3& pf : points) {
    const Vec3d p(pf);
    const double pv = bv_detail::dot(p, v), pw = bv_detail::dot(p, w);
    lo_v = std::min(lo_v, pv);
    hi_v = std::max(hi_v, pv);
    lo_w = std::min(lo_w, pw);
    hi_w = std::max(hi_w, pw);
  }
  const double cv = 0.5 * (lo_v + hi_v), cw = 0.5 * (lo_w + hi_w);
  std::vector<std::array<double, 2>> axial_radial(points.size());  // (s, squared distance from the line)
  double min_radius2 = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3d p(points[i]);
    const double dv = bv_detail::dot(p, v) - cv, dw = bv_detail::dot(p, w) - cw;
    axial_radial[i] = {bv_detail::dot(p, u), dv * dv + dw * dw};
    min_radius2 = std::max(min_radius2, axial_radial[i][1]);
  }
  const Vec3d origin = v * cv + w * cw;
  Candidate best;
  for (double factor : kRadiusFactors) {
    const double r = std::sqrt(min_radius2) * factor;
    const double r2 = std::max(r * r, min_radius2);
    // The segment [start, end] must meet every point's reach [s - h, s + h]: end >= the largest lower end and
    // start <= the smallest upper end. When the largest lower end is the smaller one, one point meets all reaches.
    double need_end = -std::numeric_limits<double>::infinity(), need_start = -need_end;
    for (const auto& [s, d2] : axial_radial) {
      const double half = std::sqrt(r2 - d2);
      need_end = std::max(need_end, s - half);
      need_start = std::min(need_start, s + half);
    }
    if (need_end <= need_start) need_end = need_start = 0.5 * (need_end + need_start);
    const double start = need_start, end = need_end;
    const double length = end - start;
    const double area = 2.0 * std::numbers::pi * std::sqrt(r2) * length + 4.0 * std::numbers::pi * r2;
    if (area < best.area) best = {origin + u * start, origin + u * end, std::sqrt(r2), area};
    if (length == 0.0) break;  // larger radii only grow the sphere
  }
  return best;
}

/// Distance from p to the segment [a, b], in double.
double segment_distance(const Vec3d& p, const Vec3d& a, const Vec3d& b) {
  const Vec3d ab = b - a;
  const double ab2 = bv_detail::length_squared(ab);
  const double t = ab2 > 0.0 ? std::clamp(bv_detail::dot(p - a, ab) / ab2, 0.0, 1.0) : 0.0;
  return bv_detail::length(p - (a + ab * t));
}

}  // namespace

CapsuleVolume CapsuleVolume::fit(std::span<const Vec3> points) {
  CapsuleVolume v;
  if (points.empty()) return v;
  std::vector<Vec3d> axes{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3d principal[3];
  if (bv_detail::principal_axes(points, principal)) axes.push_back(principal[0]);
  // The farthest pair among the extremal points on the k-DOP-26 directions (as DiTO's base edge).
  const std::array<std::size_t, 26> ext = bv_detail::extremal_points_26(points);
  double far2 = 0.0;
  Vec3d far_axis;
  for (int j = 0; j < 13; ++j) {
    const Vec3d e = Vec3d(points[ext[2 * j + 1]]) - Vec3d(points[ext[2 * j]]);
    if (bv_detail::length_squared(e) > far2) {
      far2 = bv_detail::length_squared(e);
      far_axis = e;
    }
  }
  if (far2 > 0.0) axes.push_back(bv_detail::normalize(far_axis));
  Candidate best;
  for (const Vec3d& u : axes) {
    const Candidate c = fit_on_axis(points, u);
    if (c.area < best.area) best = c;
  }
  // The ends go to float inside the points' box: an end of the double segment can lie past FLT_MAX when the points
  // reach it, and a float end of infinity made the radius NaN (fuzz corpus capsule-at-flt-max). Any ends enclose
  // the points, as the radius is measured from the stored ones below; a NaN end (a degenerate axis) takes the box's
  // low corner.
  AABB box;
  for (const Vec3& p : points) box.extend(p);
  const auto end_in_box = [&](const Vec3d& e) {
    Vec3 f;
    for (int k = 0; k < 3; ++k) {
      const double x = e[k];
      f[k] = x >= double(box.lo[k]) ? (x <= double(box.hi[k]) ? float(x) : box.hi[k]) : box.lo[k];
    }
    return f;
  };
  v.a = end_in_box(best.a);
  v.b = end_in_box(best.b);
  // The radius of the stored float segment, measured exactly enough (double) and rounded up.
  double radius = 0.0;
  const Vec3d a(v.a), b(v.b);
  for (const Vec3& p : points) radius = std::max(radius, segment_distance(Vec3d(p), a, b));
  v.radius = round_up_to_float(radius * (1.0 + 0x1p-50));
  return v;
}

double CapsuleVolume::segment_length() const { return bv_detail::length(Vec3d(b) - Vec3d(a)); }

AABB CapsuleVolume::bounds() const {
  if (!(radius >= 0.0f)) return AABB::empty();
  AABB box;
  for (int k = 0; k < 3; ++k) {
    box.lo[k] = round_down_to_float(std::min(double(a[k]), double(b[k])) - radius);
    box.hi[k] = round_up_to_float(std::max(double(a[k]), double(b[k])) + radius);
  }
  return box;
}

bool CapsuleVolume::contains(const Vec3& p) const {
  if (!(radius >= 0.0f)) return false;
  const double scale = std::max(double(max_component(abs(a))), double(max_component(abs(b)))) + radius;
  return segment_distance(Vec3d(p), Vec3d(a), Vec3d(b)) <= double(radius) + 4.0 * 0x1p-24 * scale;
}

}  // namespace rayaccel
