// k-DOP fitting and measuring: exact area (each face clipped by the other half-spaces, Sutherland & Hodgman 1974, in
// double) and volume (cones from an interior point over the faces).
#include "rayaccel/bv/kdop_volume.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>

#include "fit_support.h"
#include "rayaccel/core/float_rounding.h"

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

struct Measure {
  double area = 0.0;
  double volume = 0.0;
};

/// Area and volume of the k-DOP. Face plane g is slab g / 2's lo side (g even: lo - s <= 0, s the projection on the
/// slab direction) or hi side (g odd: s - hi <= 0). Each face starts as the bounding box's face (coordinate planes)
/// or a square larger than the box (diagonal planes) and is clipped by every other half-space; vertices carry their k/2 projections, so the distance to any plane is one
/// subtraction and a crossing vertex interpolates them (the projections are linear).
template <int K>
Measure measure(const KdopVolume<K>& kdop) {
  constexpr int kSlabs = KdopVolume<K>::kSlabs;
  constexpr int kPlanes = 2 * kSlabs;
  constexpr auto dirs = kdop_directions<K>();
  struct Vertex {
    Vec3d p;
    std::array<double, kSlabs> proj;
  };
  const auto beyond = [&](const Vertex& v, int g) {
    const int j = g >> 1;
    return (g & 1) ? v.proj[j] - double(kdop.hi[j]) : double(kdop.lo[j]) - v.proj[j];
  };
  const AABB box = kdop.bounds();
  const Vec3d lo(box.lo), hi(box.hi);
  const Vec3d center = (lo + hi) * 0.5;
  const double diagonal = bv_detail::length(hi - lo);
  const double scale = diagonal + std::max(bv_detail::length(lo), bv_detail::length(hi));
  const double half_size = 2.0 * diagonal + 1e-30;
  // Points within this of a plane count as on it, so coincident planes (flat k-DOPs) do not clip each other away.
  const double tolerance = 2e-12 * scale;
  // A convex polygon gains at most one vertex per clip (two new, at least one dropped); the pool has room for two
  // new vertices per clip, and the capacity checks only guard against rounding.
  std::array<Vertex, 4 + 2 * kPlanes> pool;
  std::array<int, pool.size()> index_buffers[2];
  std::array<double, pool.size()> dist;
  Measure m;
  for (int f = 0; f < kPlanes; ++f) {
    const Vec3d dir(dirs[f >> 1]);
    const double norm = bv_detail::length(dir);
    const Vec3d unit = dir * ((f & 1) ? 1.0 / norm : -1.0 / norm);
    const double offset = (f & 1) ? double(kdop.hi[f >> 1]) : -double(kdop.lo[f >> 1]);
    const double height = (offset / norm - bv_detail::dot(unit, center));
    const Vec3d foot = center + unit * height;
    const Vec3d helper = std::fabs(unit.x) < 0.5 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
    const Vec3d t1 = bv_detail::normalize(bv_detail::cross(unit, helper));
    const Vec3d t2 = bv_detail::cross(unit, t1);
    const auto make_vertex = [&](int slot, const Vec3d& p) {
      pool[slot].p = p;
      for (int j = 0; j < kSlabs; ++j) pool[slot].proj[j] = bv_detail::dot(Vec3d(dirs[j]), p);
    };
    if (f < 6) {
      // A coordinate face starts as the bounding box's face, which the other axis planes cannot cut.
      const int axis = f >> 1, u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int c = 0; c < 4; ++c) {
        Vec3d corner;
        corner[axis] = (f & 1) ? hi[axis] : lo[axis];
        corner[u] = (c == 1 || c == 2) ? hi[u] : lo[u];
        corner[v] = (c >= 2) ? hi[v] : lo[v];
        make_vertex(c, corner);
      }
    } else {
      make_vertex(0, foot + (t1 + t2) * half_size);
      make_vertex(1, foot + (t2 - t1) * half_size);
      make_vertex(2, foot - (t1 + t2) * half_size);
      make_vertex(3, foot + (t1 - t2) * half_size);
    }
    int pool_size = 4;
    int* poly = index_buffers[0].data();
    int* next = index_buffers[1].data();
    int count = 4;
    for (int i = 0; i < 4; ++i) poly[i] = i;
    for (int g = f < 6 ? 6 : 0; g < kPlanes && count > 0; ++g) {
      if (g == f) continue;
      bool cuts = false;
      for (int i = 0; i < count; ++i) {
        dist[i] = beyond(pool[poly[i]], g) - tolerance;
        cuts |= dist[i] > 0.0;
      }
      if (!cuts) continue;
      int kept = 0;
      for (int i = 0; i < count; ++i) {
        const int k = i + 1 == count ? 0 : i + 1;
        const double da = dist[i], db = dist[k];
        if (da <= 0.0 && kept < int(pool.size())) next[kept++] = poly[i];
        if (((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) && kept < int(pool.size()) &&
            pool_size < int(pool.size())) {
          const Vertex &a = pool[poly[i]], &b = pool[poly[k]];
          const double t = da / (da - db);
          Vertex& v = pool[pool_size];
          v.p = a.p + (b.p - a.p) * t;
          for (int j = 0; j < kSlabs; ++j) v.proj[j] = a.proj[j] + (b.proj[j] - a.proj[j]) * t;
          next[kept++] = pool_size++;
        }
      }
      std::swap(poly, next);
      count = kept;
    }
    Vec3d sum;
    for (int i = 1; i + 1 < count; ++i) {
      sum = sum + bv_detail::cross(pool[poly[i]].p - pool[poly[0]].p, pool[poly[i + 1]].p - pool[poly[0]].p);
    }
    const double area = 0.5 * bv_detail::length(sum);
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
