// k-DOP fitting and measuring. Area and volume are exact: each face polygon is the face plane clipped by every
// other half-space (Sutherland & Hodgman 1974, applied to a convex polygon in 3D), and the volume sums the cones
// from an interior point over the faces (divergence theorem).
#include "rayaccel/bv/kdop_volume.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <tuple>

#include "fit_support.h"
#include "rayaccel/geometry/float_rounding.h"

namespace rayaccel {
namespace {

using bv_detail::Vec3d;

/// Relative fit margin: 4 float ulps of the largest coordinate magnitude. The k-DOP ray test's slack covers the ray
/// origin's magnitude; this margin covers the fitted points' own, so together they bound the triangle test's
/// rounding (a few ulps of |v - o|) for hits on the fitted points.
constexpr double kFitMargin = 0x1p-22;

/// The absolute per-coordinate margin for a point set: kFitMargin times its largest |coordinate| (at least the
/// smallest normal float, so a set at the origin still gets a positive margin).
double fit_margin(std::span<const Vec3> points) {
  float scale = 0.0f;
  for (const Vec3& p : points) scale = std::max(scale, max_component(abs(p)));
  return std::max(kFitMargin * scale, double(std::numeric_limits<float>::min()));
}

/// The half-space dot(normal, p) <= offset.
struct HalfSpace {
  Vec3d normal;
  double offset;
};

/// A convex polygon with room for the start square plus one vertex per clip.
struct Polygon {
  std::array<Vec3d, 48> v;
  int count = 0;
};

/// Clips in by the half-space into out; returns false (out untouched) when nothing is cut off.
bool clip(const Polygon& in, const HalfSpace& h, double tolerance, Polygon& out) {
  std::array<double, std::tuple_size_v<decltype(Polygon::v)>> dist;
  bool cuts = false;
  for (int i = 0; i < in.count; ++i) {
    dist[i] = bv_detail::dot(h.normal, in.v[i]) - h.offset - tolerance;
    cuts |= dist[i] > 0.0;
  }
  if (!cuts) return false;
  out.count = 0;
  for (int i = 0; i < in.count; ++i) {
    const int j = i + 1 == in.count ? 0 : i + 1;
    const Vec3d& a = in.v[i];
    const double da = dist[i], db = dist[j];
    // A convex polygon gains at most one vertex per clip; the capacity check only guards against rounding.
    if (da <= 0.0 && out.count < int(out.v.size())) out.v[out.count++] = a;
    if (((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) && out.count < int(out.v.size()))
      out.v[out.count++] = a + (in.v[j] - a) * (da / (da - db));
  }
  return true;
}

double polygon_area(const Polygon& p) {
  Vec3d sum;
  for (int i = 1; i + 1 < p.count; ++i) sum = sum + bv_detail::cross(p.v[i] - p.v[0], p.v[i + 1] - p.v[0]);
  return 0.5 * bv_detail::length(sum);
}

struct Measure {
  double area = 0.0;
  double volume = 0.0;
};

template <int K>
Measure measure(const KdopVolume<K>& kdop) {
  constexpr auto dirs = kdop_directions<K>();
  constexpr int n = 2 * KdopVolume<K>::kSlabs;
  std::array<HalfSpace, n> planes;
  for (int j = 0; j < KdopVolume<K>::kSlabs; ++j) {
    const Vec3d d(dirs[j]);
    planes[2 * j] = {d * -1.0, -double(kdop.lo[j])};
    planes[2 * j + 1] = {d, double(kdop.hi[j])};
  }
  const Vec3d lo(kdop.bounds().lo), hi(kdop.bounds().hi);
  const Vec3d center = (lo + hi) * 0.5;
  const double diagonal = bv_detail::length(hi - lo);
  const double scale = diagonal + std::max(bv_detail::length(lo), bv_detail::length(hi));
  const double half_size = 2.0 * diagonal + 1e-30;
  std::array<double, n> tolerance;
  for (int g = 0; g < n; ++g) tolerance[g] = 1e-12 * scale * bv_detail::length(planes[g].normal);
  Measure m;
  for (int f = 0; f < n; ++f) {
    const double norm = bv_detail::length(planes[f].normal);
    const Vec3d unit = planes[f].normal * (1.0 / norm);
    const double height = (planes[f].offset - bv_detail::dot(planes[f].normal, center)) / norm;
    const Vec3d foot = center + unit * height;
    // A square on the face plane, larger than the bounding box, cut down by every other half-space.
    const Vec3d helper = std::fabs(unit.x) < 0.5 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
    const Vec3d t1 = bv_detail::normalize(bv_detail::cross(unit, helper));
    const Vec3d t2 = bv_detail::cross(unit, t1);
    Polygon buffers[2];
    Polygon* a = &buffers[0];
    Polygon* b = &buffers[1];
    a->count = 4;
    a->v[0] = foot + (t1 + t2) * half_size;
    a->v[1] = foot + (t2 - t1) * half_size;
    a->v[2] = foot - (t1 + t2) * half_size;
    a->v[3] = foot + (t1 - t2) * half_size;
    for (int g = 0; g < n && a->count > 0; ++g) {
      if (g == f) continue;
      if (clip(*a, planes[g], tolerance[g], *b)) std::swap(a, b);
    }
    const double area = a->count >= 3 ? polygon_area(*a) : 0.0;
    m.area += area;
    m.volume += area * height / 3.0;
  }
  return m;
}

}  // namespace

template <int K>
KdopVolume<K>::KdopVolume() {
  std::fill(lo, lo + kSlabs, std::numeric_limits<float>::infinity());
  std::fill(hi, hi + kSlabs, -std::numeric_limits<float>::infinity());
}

template <int K>
KdopVolume<K> KdopVolume<K>::fit(std::span<const Vec3> points) {
  KdopVolume v;
  if (points.empty()) return v;
  constexpr auto dirs = kdop_directions<K>();
  std::array<double, kSlabs> mn, mx;
  mn.fill(std::numeric_limits<double>::infinity());
  mx.fill(-std::numeric_limits<double>::infinity());
  for (const Vec3& p : points) {
    for (int j = 0; j < kSlabs; ++j) {
      const double s = kdop_project(dirs[j], p);
      mn[j] = std::min(mn[j], s);
      mx[j] = std::max(mx[j], s);
    }
  }
  const double margin = fit_margin(points);
  for (int j = 0; j < kSlabs; ++j) {
    const double m = margin * (std::fabs(dirs[j].x) + std::fabs(dirs[j].y) + std::fabs(dirs[j].z));
    v.lo[j] = round_down_to_float(mn[j] - m);
    v.hi[j] = round_up_to_float(mx[j] + m);
  }
  return v;
}

template <int K>
bool KdopVolume<K>::is_empty() const {
  for (int j = 0; j < kSlabs; ++j) {
    if (!(lo[j] <= hi[j])) return true;
  }
  return false;
}

template <int K>
float KdopVolume<K>::surface_area() const {
  return is_empty() ? 0.0f : static_cast<float>(measure(*this).area);
}

template <int K>
float KdopVolume<K>::volume() const {
  return is_empty() ? 0.0f : static_cast<float>(measure(*this).volume);
}

template <int K>
AABB KdopVolume<K>::bounds() const {
  if (is_empty()) return AABB::empty();
  return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
}

template <int K>
bool KdopVolume<K>::contains(const Vec3& p) const {
  constexpr auto dirs = kdop_directions<K>();
  for (int j = 0; j < kSlabs; ++j) {
    const double s = kdop_project(dirs[j], p);
    const double slack = 4.0 * 0x1p-24 * std::max(std::fabs(double(lo[j])), std::fabs(double(hi[j])));
    if (!(s >= lo[j] - slack && s <= hi[j] + slack)) return false;
  }
  return true;
}

template struct KdopVolume<14>;
template struct KdopVolume<18>;
template struct KdopVolume<26>;

}  // namespace rayaccel
