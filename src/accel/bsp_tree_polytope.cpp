// Convex polytopes for BSP cells (Ize, Wald & Parker 2008): clipping by a plane (faces clipped with
// geometry/clip_polygon.h, the cut closed by a large square clipped to every face plane) and split surface areas.
#include <algorithm>
#include <cmath>
#include <vector>

#include "rayaccel/accel/bsp_tree.h"
#include "rayaccel/geometry/clip_polygon.h"

namespace rayaccel {

namespace {

struct VectorArea {
  double x = 0.0, y = 0.0, z = 0.0;
  double length() const { return std::sqrt(x * x + y * y + z * z); }
};

/// Half the sum of (p_i - p_0) x (p_i+1 - p_0): the polygon's area times its unit normal (right-hand rule).
VectorArea vector_area(const Vec3* p, int n) {
  VectorArea a;
  for (int i = 1; i + 1 < n; ++i) {
    const double ux = double(p[i].x) - p[0].x, uy = double(p[i].y) - p[0].y, uz = double(p[i].z) - p[0].z;
    const double vx = double(p[i + 1].x) - p[0].x, vy = double(p[i + 1].y) - p[0].y,
                 vz = double(p[i + 1].z) - p[0].z;
    a.x += 0.5 * (uy * vz - uz * vy);
    a.y += 0.5 * (uz * vx - ux * vz);
    a.z += 0.5 * (ux * vy - uy * vx);
  }
  return a;
}

/// Scratch buffers for face clipping (reused, so split_areas() allocates nothing once warmed up).
std::vector<Vec3>& scratch(int which, std::size_t size) {
  thread_local std::vector<Vec3> buffers[2];
  if (buffers[which].size() < size) buffers[which].resize(size);
  return buffers[which];
}

/// A unit vector orthogonal to n.
Vec3 any_orthogonal(const Vec3& n) {
  const Vec3 helper = std::fabs(n.x) < 0.6f ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  return normalize(cross(n, helper));
}

}  // namespace

const std::vector<Vec3>& kdop13_directions() {
  static const std::vector<Vec3> directions = [] {
    const Vec3 raw[13] = {{1, 0, 0},  {0, 1, 0},  {0, 0, 1},  {1, 1, 1},  {1, 1, -1}, {1, -1, 1}, {-1, 1, 1},
                          {1, 1, 0},  {1, -1, 0}, {1, 0, 1},  {1, 0, -1}, {0, 1, 1},  {0, 1, -1}};
    std::vector<Vec3> out;
    for (const Vec3& d : raw) out.push_back(normalize(d));
    return out;
  }();
  return directions;
}

Polytope Polytope::from_box(const AABB& box) {
  Polytope p;
  if (box.is_empty()) return p;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int high = 0; high < 2; ++high) {
      Face f;
      f.normal[axis] = high ? 1.0f : -1.0f;
      const float c = high ? box.hi[axis] : box.lo[axis];
      f.offset = high ? double(c) : -double(c);
      const float us[4] = {box.lo[u], box.hi[u], box.hi[u], box.lo[u]};
      const float vs[4] = {box.lo[v], box.lo[v], box.hi[v], box.hi[v]};
      for (int k = 0; k < 4; ++k) {
        Vec3 q;
        q[axis] = c;
        q[u] = us[k];
        q[v] = vs[k];
        f.vertices.push_back(q);
      }
      // (u, v) counter-clockwise faces +axis; reverse on the low side so every face winds outward.
      if (!high) std::reverse(f.vertices.begin(), f.vertices.end());
      p.faces_.push_back(std::move(f));
    }
  }
  return p;
}

double Polytope::surface_area() const {
  double area = 0.0;
  for (const Face& f : faces_) area += polygon_area(f.vertices.data(), int(f.vertices.size()));
  return area;
}

void Polytope::extent(const Vec3& n, double& lo, double& hi) const {
  lo = std::numeric_limits<double>::infinity();
  hi = -lo;
  for (const Face& f : faces_) {
    for (const Vec3& p : f.vertices) {
      const double s = double(n.x) * p.x + double(n.y) * p.y + double(n.z) * p.z;
      lo = std::min(lo, s);
      hi = std::max(hi, s);
    }
  }
}

void Polytope::split_areas(const Vec3& n, double d, double& below, double& above) const {
  double area_below = 0.0, area_above = 0.0;
  VectorArea sum_below, sum_above;
  for (const Face& f : faces_) {
    const int m = int(f.vertices.size());
    std::vector<Vec3>& out = scratch(0, std::size_t(m) + 1);
    int k = clip_polygon_to_halfspace(f.vertices.data(), m, n, d, out.data());
    if (k >= 3) {
      area_below += polygon_area(out.data(), k);
      const VectorArea a = vector_area(out.data(), k);
      sum_below.x += a.x; sum_below.y += a.y; sum_below.z += a.z;
    }
    k = clip_polygon_to_halfspace(f.vertices.data(), m, -n, -d, out.data());
    if (k >= 3) {
      area_above += polygon_area(out.data(), k);
      const VectorArea a = vector_area(out.data(), k);
      sum_above.x += a.x; sum_above.y += a.y; sum_above.z += a.z;
    }
  }
  below = area_below + sum_below.length();
  above = area_above + sum_above.length();
}

Polytope Polytope::clip(const Vec3& n, double d, bool keep_below) const {
  const Vec3 m = keep_below ? n : -n;  // outward normal of the cut face
  const double md = keep_below ? d : -d;
  Polytope out;
  AABB bounds;
  Vec3 centroid;
  std::size_t count = 0;
  for (const Face& f : faces_) {
    for (const Vec3& p : f.vertices) {
      bounds.extend(p);
      centroid += p;
      ++count;
    }
    Face g;
    g.normal = f.normal;
    g.offset = f.offset;
    g.vertices.resize(f.vertices.size() + 1);
    const int k = clip_polygon_to_halfspace(f.vertices.data(), int(f.vertices.size()), m, md, g.vertices.data());
    if (k < 3) continue;
    g.vertices.resize(std::size_t(k));
    out.faces_.push_back(std::move(g));
  }
  if (out.faces_.empty() || count == 0) return {};
  // The cut: a square in the plane, centred on the projected centroid and larger than the cell, clipped by every
  // face plane of the cell.
  centroid = centroid / float(count);
  const double lift = double(m.x) * centroid.x + double(m.y) * centroid.y + double(m.z) * centroid.z - md;
  const Vec3 center = centroid - m * float(lift);
  const float half = 2.0f * length(bounds.extent()) + std::fabs(float(lift)) + 1e-30f;
  const Vec3 u = any_orthogonal(m);
  const Vec3 v = cross(m, u);  // (u, v, m) right-handed, so the square winds counter-clockwise about m
  std::vector<Vec3> cap = {center - u * half - v * half, center + u * half - v * half, center + u * half + v * half,
                           center - u * half + v * half};
  for (const Face& f : faces_) {
    std::vector<Vec3> next(cap.size() + 1);
    const int k = clip_polygon_to_halfspace(cap.data(), int(cap.size()), f.normal, f.offset, next.data());
    next.resize(std::size_t(k));
    cap = std::move(next);
    if (cap.size() < 3) break;
  }
  if (cap.size() >= 3) {
    Face g;
    g.normal = m;
    g.offset = md;
    g.vertices = std::move(cap);
    out.faces_.push_back(std::move(g));
  }
  return out;
}

}  // namespace rayaccel
