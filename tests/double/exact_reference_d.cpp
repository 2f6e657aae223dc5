// Exact reference for the double path: see exact_reference_d.h.
#include "exact_reference_d.h"

#include <gmpxx.h>

#include <algorithm>
#include <cmath>

namespace rayaccel::exact_d {
namespace {

struct Q3 {
  mpq_class x, y, z;
};
Q3 to_q(const DVec3& v) { return {mpq_class(v.x), mpq_class(v.y), mpq_class(v.z)}; }
Q3 sub(const Q3& a, const Q3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Q3 cross(const Q3& a, const Q3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
mpq_class dot(const Q3& a, const Q3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

double norm1(const DVec3& a) { return std::fabs(a.x) + std::fabs(a.y) + std::fabs(a.z); }

/// True when double arithmetic shows beyond doubt that the ray's line misses the triangle.
bool surely_missed(const DVec3& o, const DVec3& d, const std::array<DVec3, 3>& tri) {
  const DVec3 e1 = tri[1] - tri[0], e2 = tri[2] - tri[0], s = o - tri[0];
  const DVec3 e2xd = cross(e2, d);
  const double det = -dot(e1, e2xd);
  const double scale = 1e-9 * (norm1(s) + norm1(e1) + norm1(e2)) * (norm1(e1) + norm1(e2)) * norm1(d);
  if (!(std::fabs(det) > scale) || !std::isfinite(scale)) return false;
  const double b = -dot(s, e2xd), g = -dot(e1, cross(s, d));
  const double sign = det > 0 ? 1.0 : -1.0;
  return sign * b < -scale || sign * g < -scale || sign * (det - b - g) < -scale;
}

}  // namespace

std::vector<ExactHitD> exact_hits(const std::vector<std::array<DVec3, 3>>& triangles, const RayD& ray) {
  std::vector<ExactHitD> hits;
  const DVec3& dir = ray.direction;
  if (!is_finite(ray.origin) || !is_finite(dir) || (dir.x == 0.0 && dir.y == 0.0 && dir.z == 0.0) ||
      std::isnan(ray.t_min)) {
    return hits;
  }
  const Q3 o = to_q(ray.origin), d = to_q(dir);
  const mpq_class t_min(ray.t_min);
  for (std::uint32_t id = 0; id < triangles.size(); ++id) {
    const auto& tri = triangles[id];
    if (surely_missed(ray.origin, dir, tri)) continue;
    const Q3 v0 = to_q(tri[0]);
    const Q3 e1 = sub(to_q(tri[1]), v0), e2 = sub(to_q(tri[2]), v0), s = sub(o, v0);
    // o + t d = v0 + b e1 + g e2  <=>  [e1 e2 -d] (b, g, t) = s.
    const Q3 e2xd = cross(e2, d);
    const mpq_class det = -dot(e1, e2xd);
    if (det == 0) continue;
    const mpq_class b = -dot(s, e2xd) / det;
    const mpq_class g = -dot(e1, cross(s, d)) / det;
    const mpq_class t = dot(e1, cross(e2, s)) / det;
    if (b < 0 || g < 0 || b + g > 1 || !(t > t_min)) continue;
    hits.push_back({id, t.get_d(), b.get_d(), g.get_d()});
  }
  std::sort(hits.begin(), hits.end(), [](const ExactHitD& a, const ExactHitD& b) { return a.t < b.t; });
  return hits;
}

}  // namespace rayaccel::exact_d
