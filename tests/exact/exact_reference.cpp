// Exact reference: see exact_reference.h.
#include "exact_reference.h"

#include <gmpxx.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace rayaccel::exact {
namespace {

struct Q3 {
  mpq_class x, y, z;
};

Q3 to_q(const Vec3& v) { return {mpq_class(double(v.x)), mpq_class(double(v.y)), mpq_class(double(v.z))}; }
Q3 sub(const Q3& a, const Q3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Q3 cross(const Q3& a, const Q3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
mpq_class dot(const Q3& a, const Q3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

struct D3 {
  double x, y, z;
};
D3 to_d(const Vec3& v) { return {v.x, v.y, v.z}; }
D3 sub(const D3& a, const D3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 cross(const D3& a, const D3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double norm1(const D3& a) { return std::fabs(a.x) + std::fabs(a.y) + std::fabs(a.z); }

bool ray_is_void(const Ray& r) {
  const auto finite = [](const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  return !finite(r.origin) || !finite(r.direction) ||
         (r.direction.x == 0.0f && r.direction.y == 0.0f && r.direction.z == 0.0f) || std::isnan(r.t_min) ||
         std::isnan(r.t_max) || !(r.t_min <= r.t_max);
}

/// True when double arithmetic shows, beyond any doubt, that the ray's line misses the triangle: a barycentric
/// coordinate below zero by far more than its rounding error (1e-12 relative to the terms, thousands of ulps).
bool surely_missed(const D3& o, const D3& d, const std::array<Vec3, 3>& tri) {
  const D3 v0 = to_d(tri[0]);
  const D3 e1 = sub(to_d(tri[1]), v0), e2 = sub(to_d(tri[2]), v0), s = sub(o, v0);
  // o + t d = v0 + b e1 + g e2  <=>  [e1 e2 -d] (b, g, t) = s;  D = det[e1 e2 -d] = -e1 . (e2 x d).
  const D3 e2xd = cross(e2, d);
  const double det = -dot(e1, e2xd);
  const double scale = 1e-12 * (norm1(s) + norm1(e1) + norm1(e2)) * (norm1(e1) + norm1(e2)) * norm1(d);
  if (!(std::fabs(det) > scale) || !std::isfinite(scale)) return false;
  // b = det[s e2 -d] / D = -s . (e2 x d) / D;  g = det[e1 s -d] / D = -e1 . (s x d) / D.
  const double b = -dot(s, e2xd), g = -dot(e1, cross(s, d));
  const double sign = det > 0 ? 1.0 : -1.0;
  return sign * b < -scale || sign * g < -scale || sign * (det - b - g) < -scale;
}

std::string describe(const Ray& r) {
  std::ostringstream out;
  out.precision(9);
  out << "ray o=(" << r.origin.x << ", " << r.origin.y << ", " << r.origin.z << ") d=(" << r.direction.x << ", "
      << r.direction.y << ", " << r.direction.z << ") t=[" << r.t_min << ", " << r.t_max << "]";
  return out.str();
}

}  // namespace

ExactReference::ExactReference(const TriangleMesh& mesh) {
  triangles_.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    triangles_.push_back({mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]});
  }
}

std::vector<ExactHit> ExactReference::hits_past_t_min(const Ray& ray) const {
  std::vector<ExactHit> out;
  if (ray_is_void(ray) || ray.t_min == INFINITY) return out;
  const D3 od = to_d(ray.origin), dd = to_d(ray.direction);
  const Q3 o = to_q(ray.origin), d = to_q(ray.direction);
  const bool finite_t_min = std::isfinite(ray.t_min);  // else -inf
  const mpq_class t_min(finite_t_min ? double(ray.t_min) : 0.0);
  for (std::uint32_t id = 0; id < triangles_.size(); ++id) {
    const auto& tri = triangles_[id];
    const auto finite = [](const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    if (!finite(tri[0]) || !finite(tri[1]) || !finite(tri[2])) continue;
    if (surely_missed(od, dd, tri)) continue;
    const Q3 v0 = to_q(tri[0]);
    const Q3 e1 = sub(to_q(tri[1]), v0), e2 = sub(to_q(tri[2]), v0), s = sub(o, v0);
    const Q3 e2xd = cross(e2, d);
    const mpq_class det = -dot(e1, e2xd);
    if (sgn(det) == 0) continue;  // the ray is in the plane, or the triangle has no area
    const mpq_class b = -dot(s, e2xd) / det;
    const mpq_class g = -dot(e1, cross(s, d)) / det;
    if (sgn(b) < 0 || sgn(g) < 0 || b + g > 1) continue;
    // t = det[e1 e2 s] / D = e1 . (e2 x s) / D
    const mpq_class t = dot(e1, cross(e2, s)) / det;
    if (finite_t_min && !(t > t_min)) continue;
    ExactHit h{id, t.get_d(), b.get_d(), g.get_d(), 0.0};
    // The tolerance: depth of each vertex along the dominant axis of d, in units of t.
    const D3 ad{std::fabs(dd.x), std::fabs(dd.y), std::fabs(dd.z)};
    const int axis = ad.x >= ad.y && ad.x >= ad.z ? 0 : (ad.y >= ad.z ? 1 : 2);
    double lo = INFINITY, hi = -INFINITY, far = 0.0;
    for (const Vec3& v : tri) {
      const double z = (double(v[axis]) - double(ray.origin[axis])) / double(ray.direction[axis]);
      lo = std::min(lo, z);
      hi = std::max(hi, z);
      far = std::max(far, std::fabs(z));
    }
    h.t_tolerance = (hi - lo) / 32.0 + far * 0x1p-18;
    out.push_back(h);
  }
  std::sort(out.begin(), out.end(), [](const ExactHit& a, const ExactHit& b) { return a.t < b.t; });
  return out;
}

std::string ExactReference::closest_hit_mismatch(const Ray& ray, const std::vector<ExactHit>& all, const Hit& hit) {
  const double t_min = ray.t_min, t_max = ray.t_max;
  const auto required = [&](const ExactHit& h) {  // must be found: clear of both ends of the interval
    return h.t > t_min + h.t_tolerance && h.t <= t_max - h.t_tolerance;
  };
  std::ostringstream out;
  out.precision(9);
  if (!hit.found()) {
    for (const ExactHit& h : all) {
      if (required(h)) {
        out << describe(ray) << ": missed, but it hits prim " << h.prim_id << " at exact t=" << h.t
            << " (u=" << h.u << ", v=" << h.v << ")";
        return out.str();
      }
    }
    return {};
  }
  const auto mine = std::find_if(all.begin(), all.end(), [&](const ExactHit& h) { return h.prim_id == hit.prim_id; });
  if (mine == all.end() || mine->t > t_max + mine->t_tolerance) {
    out << describe(ray) << ": reports prim " << hit.prim_id << " at t=" << hit.t
        << ", which the ray does not hit exactly in its interval";
    if (!all.empty()) out << " (closest exact hit: prim " << all.front().prim_id << " at t=" << all.front().t << ")";
    return out.str();
  }
  if (std::fabs(double(hit.t) - mine->t) > mine->t_tolerance) {
    out << describe(ray) << ": prim " << hit.prim_id << " reported at t=" << hit.t << ", exact t=" << mine->t
        << " (tolerance " << mine->t_tolerance << ")";
    return out.str();
  }
  for (const ExactHit& h : all) {
    if (required(h) && h.t + h.t_tolerance + mine->t_tolerance < mine->t) {
      out << describe(ray) << ": reports prim " << hit.prim_id << " at exact t=" << mine->t << ", but prim "
          << h.prim_id << " is hit closer, at exact t=" << h.t;
      return out.str();
    }
  }
  return {};
}

std::string ExactReference::occlusion_mismatch(const Ray& ray, const std::vector<ExactHit>& all, bool occluded) {
  std::ostringstream out;
  out.precision(9);
  if (occluded) {
    for (const ExactHit& h : all) {
      if (h.t <= double(ray.t_max) + h.t_tolerance) return {};
    }
    out << describe(ray) << ": reported occluded, but nothing is hit exactly in its interval";
    return out.str();
  }
  for (const ExactHit& h : all) {
    if (h.t > double(ray.t_min) + h.t_tolerance && h.t <= double(ray.t_max) - h.t_tolerance) {
      out << describe(ray) << ": reported not occluded, but prim " << h.prim_id << " is hit at exact t=" << h.t;
      return out.str();
    }
  }
  return {};
}

}  // namespace rayaccel::exact
