// Polytope area by clipping each face against every other half-space (Sutherland & Hodgman 1974).
#include "polytope_area.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rayaccel::bv_detail {
namespace {

/// Keeps the part of the convex polygon with dot(h.normal, p) <= h.offset + tolerance.
void clip(std::vector<Vec3d>& polygon, std::vector<Vec3d>& scratch, const Halfspace& h, double tolerance) {
  scratch.clear();
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3d& a = polygon[i];
    const Vec3d& b = polygon[i + 1 == n ? 0 : i + 1];
    const double da = dot(h.normal, a) - h.offset - tolerance;
    const double db = dot(h.normal, b) - h.offset - tolerance;
    if (da <= 0.0) scratch.push_back(a);
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) scratch.push_back(a + (b - a) * (da / (da - db)));
  }
  polygon.swap(scratch);
}

double polygon_area(const std::vector<Vec3d>& polygon) {
  Vec3d sum;
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
    sum = sum + cross(polygon[i] - polygon[0], polygon[i + 1] - polygon[0]);
  }
  return 0.5 * length(sum);
}

}  // namespace

double polytope_area(const AABB& box, std::span<const Halfspace> cuts) {
  if (box.is_empty()) return 0.0;
  const Vec3d lo(box.lo), hi(box.hi);
  const double diagonal = length(hi - lo);
  const double scale = diagonal + std::max(length(lo), length(hi));
  const double tolerance = 2e-12 * scale;
  const double half_size = 2.0 * diagonal + 1e-30;
  const Vec3d center = (lo + hi) * 0.5;
  std::vector<Halfspace> all;
  for (int a = 0; a < 3; ++a) {
    Vec3d n;
    n[a] = -1.0;
    all.push_back({n, -lo[a]});
    n[a] = 1.0;
    all.push_back({n, hi[a]});
  }
  all.insert(all.end(), cuts.begin(), cuts.end());
  std::vector<Vec3d> polygon, scratch;
  double area = 0.0;
  for (std::size_t f = 0; f < all.size(); ++f) {
    polygon.clear();
    if (f < 6) {
      // A box face starts as itself: the other box planes cannot cut it.
      const int axis = int(f) >> 1, u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int c = 0; c < 4; ++c) {
        Vec3d corner;
        corner[axis] = (f & 1) ? hi[axis] : lo[axis];
        corner[u] = (c == 1 || c == 2) ? hi[u] : lo[u];
        corner[v] = (c >= 2) ? hi[v] : lo[v];
        polygon.push_back(corner);
      }
    } else {
      const double norm = length(all[f].normal);
      if (!(norm > 0.0)) continue;
      const Vec3d unit = all[f].normal * (1.0 / norm);
      const Vec3d foot = center + unit * (all[f].offset / norm - dot(unit, center));
      const Vec3d helper = std::fabs(unit.x) < 0.5 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
      const Vec3d t1 = normalize(cross(unit, helper));
      const Vec3d t2 = cross(unit, t1);
      polygon = {foot + (t1 + t2) * half_size, foot + (t2 - t1) * half_size, foot - (t1 + t2) * half_size,
                 foot + (t1 - t2) * half_size};
    }
    for (std::size_t g = f < 6 ? 6 : 0; g < all.size() && !polygon.empty(); ++g) {
      if (g == f) continue;
      const double norm = length(all[g].normal);
      if (!(norm > 0.0)) continue;
      clip(polygon, scratch, all[g], tolerance * norm);
    }
    area += polygon_area(polygon);
  }
  return area;
}

}  // namespace rayaccel::bv_detail
