// Convex polytopes for BSP cells (Ize, Wald & Parker 2008): clipping by a plane (faces clipped with
// geometry/clip_polygon.h, the cut closed by a large square clipped to every face plane) and split surface areas.
#include <algorithm>
#include <cmath>
#include <limits>
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

/// Scratch buffer for face clipping (reused, so split_areas() allocates nothing once warmed up).
std::vector<Vec3>& scratch(std::size_t size) {
  thread_local std::vector<Vec3> buffer;
  if (buffer.size() < size) buffer.resize(size);
  return buffer;
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
      p.add_face(std::move(f));
    }
  }
  return p;
}

double Polytope::surface_area() const {
  double area = 0.0;
  for (const Face& f : faces_) area += f.area;
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

void Polytope::add_face(Face face) {
  const VectorArea a = vector_area(face.vertices.data(), int(face.vertices.size()));
  face.vector_area[0] = a.x;
  face.vector_area[1] = a.y;
  face.vector_area[2] = a.z;
  face.area = a.length();
  faces_.push_back(std::move(face));
}

Polytope::Slicer::Slicer(const Polytope& polytope, const Vec3& n) : polytope_(polytope), normal_(n) {
  for (const Face& f : polytope.faces_) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Vec3& p : f.vertices) {
      const double s = double(n.x) * p.x + double(n.y) * p.y + double(n.z) * p.z;
      lo = std::min(lo, s);
      hi = std::max(hi, s);
    }
    lo_.push_back(lo);
    hi_.push_back(hi);
  }
}

void Polytope::Slicer::split_areas(double d, double& below, double& above) const {
  double area_below = 0.0, area_above = 0.0;
  VectorArea sum_below, sum_above;
  auto add = [](VectorArea& sum, double x, double y, double z) {
    sum.x += x;
    sum.y += y;
    sum.z += z;
  };
  for (std::size_t i = 0; i < polytope_.faces_.size(); ++i) {
    const Face& f = polytope_.faces_[i];
    const double* fa = f.vector_area;
    if (hi_[i] <= d) {  // entirely below, or lying in the plane: both closed halves hold it
      area_below += f.area;
      add(sum_below, fa[0], fa[1], fa[2]);
    }
    if (lo_[i] >= d) {
      area_above += f.area;
      add(sum_above, fa[0], fa[1], fa[2]);
    }
    if (hi_[i] <= d || lo_[i] >= d) continue;
    const int m = int(f.vertices.size());
    std::vector<Vec3>& out = scratch(clip_capacity(std::size_t(m)));
    const int k = clip_polygon_to_halfspace(f.vertices.data(), m, normal_, d, out.data());
    const VectorArea b = vector_area(out.data(), k);
    area_below += b.length();
    add(sum_below, b.x, b.y, b.z);
    const double ax = fa[0] - b.x, ay = fa[1] - b.y, az = fa[2] - b.z;  // the rest of the face, same winding
    area_above += std::sqrt(ax * ax + ay * ay + az * az);
    add(sum_above, ax, ay, az);
  }
  below = area_below + sum_below.length();
  above = area_above + sum_above.length();
}

void Polytope::split_areas(const Vec3& n, double d, double& below, double& above) const {
  Slicer(*this, n).split_areas(d, below, above);
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
    g.vertices.resize(clip_capacity(f.vertices.size()));
    const int k = clip_polygon_to_halfspace(f.vertices.data(), int(f.vertices.size()), m, md, g.vertices.data());
    if (k < 3) continue;
    g.vertices.resize(std::size_t(k));
    out.add_face(std::move(g));
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
    std::vector<Vec3> next(clip_capacity(cap.size()));
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
    out.add_face(std::move(g));
  }
  return out;
}

}  // namespace rayaccel
