// OBB fitting: candidate frames from PCA (principal_axes.h), from DiTO-26 (Larsson & Kallberg 2011: frames built
// from a large base triangle of extremal points and the two tetrahedra on it), and the world axes; the frame whose
// box has the smallest surface area wins.
#include "rayaccel/bv/obb_volume.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "fit_support.h"
#include "principal_axes.h"
#include "rayaccel/core/float_rounding.h"

namespace rayaccel {
namespace {

using bv_detail::Vec3d;

struct Frame {
  Vec3d axis[3];
};

Vec3d any_perpendicular(const Vec3d& a) {
  const Vec3d abs_a{std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)};
  const Vec3d helper = abs_a.x <= abs_a.y && abs_a.x <= abs_a.z ? Vec3d{1, 0, 0}
                       : abs_a.y <= abs_a.z                      ? Vec3d{0, 1, 0}
                                                                 : Vec3d{0, 0, 1};
  return bv_detail::normalize(bv_detail::cross(a, helper));
}

/// A right-handed orthonormal frame whose first axis is along a0 and second in the plane of a0 and a1 (any
/// perpendicular when a1 is parallel to a0). Requires a0 != 0.
Frame make_frame(const Vec3d& a0, const Vec3d& a1) {
  Frame f;
  f.axis[0] = bv_detail::normalize(a0);
  const Vec3d b = a1 - f.axis[0] * bv_detail::dot(a1, f.axis[0]);
  f.axis[1] = bv_detail::length_squared(b) > 1e-24 * bv_detail::length_squared(a1) && bv_detail::length_squared(b) > 0
                  ? bv_detail::normalize(b)
                  : any_perpendicular(f.axis[0]);
  f.axis[2] = bv_detail::cross(f.axis[0], f.axis[1]);
  return f;
}

/// Surface area of the box of the points in the frame.
template <class Point>
double frame_area(std::span<const Point> points, const Frame& f) {
  double lo[3], hi[3];
  std::fill(lo, lo + 3, std::numeric_limits<double>::infinity());
  std::fill(hi, hi + 3, -std::numeric_limits<double>::infinity());
  for (const Point& pf : points) {
    const Vec3d p(pf);
    for (int a = 0; a < 3; ++a) {
      const double s = bv_detail::dot(f.axis[a], p);
      lo[a] = std::min(lo[a], s);
      hi[a] = std::max(hi[a], s);
    }
  }
  const double ex = hi[0] - lo[0], ey = hi[1] - lo[1], ez = hi[2] - lo[2];
  return 2.0 * (ex * ey + ey * ez + ez * ex);
}

/// PCA frame: the points' principal axes, largest variance first. False when the points are all equal.
bool pca_frame(std::span<const Vec3> points, Frame& frame) {
  Vec3d axes[3];
  if (!bv_detail::principal_axes(points, axes)) return false;
  frame = make_frame(axes[0], axes[1]);
  return true;
}

/// DiTO-26: candidate frames from the extremal points on the 13 k-DOP-26 directions; returns the frame whose box
/// of those extremal points has the smallest area. False when all points coincide.
bool dito_frame(std::span<const Vec3> points, Frame& best) {
  const std::array<std::size_t, 26> arg = bv_detail::extremal_points_26(points);
  const std::vector<Vec3d> ext = bv_detail::distinct_points(points, arg);
  // Base triangle: the farthest extremal pair, then the extremal point farthest from their line.
  int pair = 0;
  double pair_d2 = -1.0;
  for (int j = 0; j < 13; ++j) {
    const double d2 = bv_detail::length_squared(Vec3d(points[arg[2 * j + 1]]) - Vec3d(points[arg[2 * j]]));
    if (d2 > pair_d2) { pair_d2 = d2; pair = j; }
  }
  if (pair_d2 <= 0.0) return false;
  const Vec3d p0(points[arg[2 * pair]]), p1(points[arg[2 * pair + 1]]);
  const Vec3d e0 = bv_detail::normalize(p1 - p0);
  Vec3d p2 = p0;
  double line_d2 = 0.0;
  for (const Vec3d& q : ext) {
    const Vec3d r = q - p0;
    const double d2 = bv_detail::length_squared(r - e0 * bv_detail::dot(r, e0));
    if (d2 > line_d2) { line_d2 = d2; p2 = q; }
  }
  std::vector<Frame> candidates;
  if (line_d2 <= 1e-24 * pair_d2) {
    candidates.push_back(make_frame(e0, any_perpendicular(e0)));
  } else {
    const auto add_triangle = [&](const Vec3d& a, const Vec3d& b, const Vec3d& c) {
      const Vec3d n = bv_detail::cross(b - a, c - a);
      if (bv_detail::length_squared(n) == 0.0) return;
      for (const Vec3d& edge : {b - a, c - b, a - c}) {
        if (bv_detail::length_squared(edge) > 0.0) candidates.push_back(make_frame(n, edge));
      }
    };
    add_triangle(p0, p1, p2);
    // The ditetrahedron: the extremal points farthest above and below the base triangle's plane.
    const Vec3d n = bv_detail::normalize(bv_detail::cross(p1 - p0, p2 - p0));
    Vec3d above = p0, below = p0;
    double h_above = 0.0, h_below = 0.0;
    for (const Vec3d& q : ext) {
      const double h = bv_detail::dot(q - p0, n);
      if (h > h_above) { h_above = h; above = q; }
      if (h < h_below) { h_below = h; below = q; }
    }
    for (const Vec3d& apex : {above, below}) {
      add_triangle(p0, p1, apex);
      add_triangle(p1, p2, apex);
      add_triangle(p2, p0, apex);
    }
  }
  double best_area = std::numeric_limits<double>::infinity();
  for (const Frame& f : candidates) {
    const double area = frame_area(std::span<const Vec3d>(ext), f);
    if (area < best_area) { best_area = area; best = f; }
  }
  return true;
}

ObbVolume box_in_frame(std::span<const Vec3> points, const Frame& frame) {
  ObbVolume v;
  Vec3 axis[3];
  Vec3d axis_d[3];
  for (int a = 0; a < 3; ++a) {
    axis[a] = bv_detail::to_float(frame.axis[a]);
    axis_d[a] = Vec3d(axis[a]);  // the box is exact for the stored float axes
  }
  double lo[3], hi[3];
  std::fill(lo, lo + 3, std::numeric_limits<double>::infinity());
  std::fill(hi, hi + 3, -std::numeric_limits<double>::infinity());
  for (const Vec3& pf : points) {
    const Vec3d p(pf);
    for (int a = 0; a < 3; ++a) {
      const double s = bv_detail::dot(axis_d[a], p);
      lo[a] = std::min(lo[a], s);
      hi[a] = std::max(hi[a], s);
    }
  }
  Vec3d center;
  for (int a = 0; a < 3; ++a) center = center + axis_d[a] * (0.5 * (lo[a] + hi[a]));
  v.box.center = bv_detail::to_float(center);
  const Vec3d c(v.box.center);
  double reach = 0.0;
  for (int a = 0; a < 3; ++a) {
    v.box.axis[a] = axis[a];
    const double s = bv_detail::dot(axis_d[a], c);
    v.box.half[a] = round_up_to_float(std::max(hi[a] - s, s - lo[a]));
    reach += v.box.half[a];
  }
  v.box.reach = round_up_to_float(reach);
  return v;
}

}  // namespace

ObbVolume ObbVolume::fit_with_axes(std::span<const Vec3> points, const Vec3& axis0, const Vec3& axis1) {
  if (points.empty()) return {};
  const Vec3d a0(axis0);
  return box_in_frame(points, make_frame(bv_detail::length_squared(a0) > 0 ? a0 : Vec3d{1, 0, 0}, Vec3d(axis1)));
}

ObbVolume ObbVolume::fit(std::span<const Vec3> points) {
  if (points.empty()) return {};
  std::vector<Frame> frames{Frame{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}};
  Frame f;
  if (pca_frame(points, f)) frames.push_back(f);
  if (dito_frame(points, f)) frames.push_back(f);
  ObbVolume best;
  for (const Frame& frame : frames) {
    const ObbVolume candidate = box_in_frame(points, frame);
    if (best.is_empty() || candidate.surface_area() < best.surface_area()) best = candidate;
  }
  return best;
}

AABB ObbVolume::bounds() const {
  if (is_empty()) return AABB::empty();
  AABB b;
  for (int k = 0; k < 3; ++k) {
    double extent = 0.0;
    for (int a = 0; a < 3; ++a) extent += std::fabs(double(box.axis[a][k])) * box.half[a];
    extent *= 1.0 + 0x1p-20;  // the stored axes are orthonormal only up to float rounding
    b.lo[k] = round_down_to_float(double(box.center[k]) - extent);
    b.hi[k] = round_up_to_float(double(box.center[k]) + extent);
  }
  return b;
}

bool ObbVolume::contains(const Vec3& p) const {
  if (is_empty()) return false;
  const Vec3d d = Vec3d(p) - Vec3d(box.center);
  const double slack = 4.0 * 0x1p-24 * (double(max_component(abs(box.center))) + box.reach);
  for (int a = 0; a < 3; ++a) {
    if (std::fabs(bv_detail::dot(Vec3d(box.axis[a]), d)) > double(box.half[a]) + slack) return false;
  }
  return true;
}

}  // namespace rayaccel
