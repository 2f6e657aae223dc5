// Quickhull in 3D (Barber, Dobkin, Huhdanpaa 1996) for tightness reports: triangular faces with neighbor links and
// outside-point sets; each step adds the farthest outside point, removes the faces it sees and fans new faces from
// the horizon. Flat sets fall back to a 2D monotone-chain hull (Andrew 1979).
#include <algorithm>
#include <cmath>
#include <vector>

#include "convex_hull.h"
#include "fit_support.h"
#include "rayaccel/bv/tightness.h"

namespace rayaccel {
namespace {

using bv_detail::ConvexHull;
using bv_detail::Vec3d;

struct Face {
  int v[3];       // counterclockwise seen from outside
  int nb[3];      // face across edge (v[i], v[i+1])
  Vec3d normal;   // unit, outward
  double offset;  // dot(normal, p) on the plane
  std::vector<int> outside;
  bool alive = true;
  int stamp = -1;
};

double cross2(double ox, double oy, double ax, double ay, double bx, double by) {
  return (ax - ox) * (by - oy) - (ay - oy) * (bx - ox);
}

/// The 2D convex hull of (u, v) pairs by Andrew's monotone chain, counterclockwise, without repeated points.
std::vector<std::pair<double, double>> hull_2d(std::vector<std::pair<double, double>> pts) {
  std::sort(pts.begin(), pts.end());
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  if (pts.size() < 3) return {};
  std::vector<std::pair<double, double>> hull(2 * pts.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross2(hull[k - 2].first, hull[k - 2].second, hull[k - 1].first, hull[k - 1].second,
                            pts[i].first, pts[i].second) <= 0)
      --k;
    hull[k++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross2(hull[k - 2].first, hull[k - 2].second, hull[k - 1].first, hull[k - 1].second,
                                pts[i].first, pts[i].second) <= 0)
      --k;
    hull[k++] = pts[i];
  }
  hull.resize(k - 1);  // the chain ends where it started
  return hull;
}

class Quickhull {
 public:
  Quickhull(std::span<const Vec3> points) {
    pts_.reserve(points.size());
    for (const Vec3& p : points) pts_.emplace_back(p);
  }

  ConvexHull run() {
    if (pts_.size() < 3) return {};
    double scale = 0.0;
    for (const Vec3d& p : pts_) scale = std::max({scale, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
    eps_ = 1e-11 * scale;
    int simplex[4];
    const int found = initial_simplex(simplex);
    if (found < 3) return {};
    if (found == 3) return flat_hull(simplex);
    build_tetrahedron(simplex);
    std::vector<int> work;
    for (int f = 0; f < 4; ++f) work.push_back(f);
    while (!work.empty()) {
      const int f = work.back();
      work.pop_back();
      if (!faces_[f].alive || faces_[f].outside.empty()) continue;
      add_point(f, work);
    }
    ConvexHull hull;
    for (const Face& face : faces_) {
      if (!face.alive) continue;
      const Vec3d &a = pts_[face.v[0]], &b = pts_[face.v[1]], &c = pts_[face.v[2]];
      const double area = 0.5 * bv_detail::length(bv_detail::cross(b - a, c - a));
      hull.measure.area += area;
      hull.measure.volume += area * (face.offset - bv_detail::dot(face.normal, interior_)) / 3.0;
      hull.facets.push_back({face.normal, face.offset, area, false});
    }
    return hull;
  }

 private:
  double distance(const Face& f, const Vec3d& p) const { return bv_detail::dot(f.normal, p) - f.offset; }

  /// Indices of a farthest pair, the point farthest from its line and the point farthest from their plane. Returns
  /// how many of them are non-degenerate (4 for a solid hull).
  int initial_simplex(int s[4]) {
    int ext[6] = {0, 0, 0, 0, 0, 0};
    for (int i = 0; i < int(pts_.size()); ++i) {
      for (int a = 0; a < 3; ++a) {
        if (pts_[i][a] < pts_[ext[2 * a]][a]) ext[2 * a] = i;
        if (pts_[i][a] > pts_[ext[2 * a + 1]][a]) ext[2 * a + 1] = i;
      }
    }
    double best = -1.0;
    for (int i = 0; i < 6; ++i) {
      for (int j = i + 1; j < 6; ++j) {
        const double d = bv_detail::length_squared(pts_[ext[i]] - pts_[ext[j]]);
        if (d > best) { best = d; s[0] = ext[i]; s[1] = ext[j]; }
      }
    }
    if (std::sqrt(best) <= eps_) return 1;
    const Vec3d dir = bv_detail::normalize(pts_[s[1]] - pts_[s[0]]);
    best = -1.0;
    for (int i = 0; i < int(pts_.size()); ++i) {
      const Vec3d r = pts_[i] - pts_[s[0]];
      const double d = bv_detail::length_squared(r - dir * bv_detail::dot(r, dir));
      if (d > best) { best = d; s[2] = i; }
    }
    if (std::sqrt(best) <= eps_) return 2;
    plane_normal_ = bv_detail::normalize(bv_detail::cross(pts_[s[1]] - pts_[s[0]], pts_[s[2]] - pts_[s[0]]));
    best = -1.0;
    for (int i = 0; i < int(pts_.size()); ++i) {
      const double d = std::fabs(bv_detail::dot(plane_normal_, pts_[i] - pts_[s[0]]));
      if (d > best) { best = d; s[3] = i; }
    }
    return best <= eps_ ? 3 : 4;
  }

  /// A flat set: both sides of its plane (each with the polygon's area) and the polygon's edges, whose outward
  /// normals lie in the plane (weighted by their length).
  ConvexHull flat_hull(const int s[3]) const {
    const Vec3d u = bv_detail::normalize(pts_[s[1]] - pts_[s[0]]);
    const Vec3d v = bv_detail::cross(plane_normal_, u);
    std::vector<std::pair<double, double>> uv;
    uv.reserve(pts_.size());
    for (const Vec3d& p : pts_) uv.emplace_back(bv_detail::dot(p, u), bv_detail::dot(p, v));
    const auto polygon = hull_2d(std::move(uv));
    double area2 = 0.0;
    ConvexHull hull;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const auto& [x0, y0] = polygon[i];
      const auto& [x1, y1] = polygon[i + 1 == polygon.size() ? 0 : i + 1];
      area2 += x0 * y1 - x1 * y0;
      // Counterclockwise in (u, v): the outward normal of edge (dx, dy) is (dy, -dx).
      const Vec3d outward = u * (y1 - y0) - v * (x1 - x0);
      const Vec3d normal = bv_detail::normalize(outward);
      // The normal lies in the plane, so the plane's own offset does not enter the support.
      hull.facets.push_back({normal, bv_detail::dot(normal, u * x0 + v * y0), bv_detail::length(outward), true});
    }
    const double area = 0.5 * std::fabs(area2);
    hull.measure = {2.0 * area, 0.0};
    const double height = bv_detail::dot(plane_normal_, pts_[s[0]]);
    hull.facets.push_back({plane_normal_, height, area, false});
    hull.facets.push_back({plane_normal_ * -1.0, -height, area, false});
    return hull;
  }

  int make_face(int a, int b, int c) {
    Face f;
    f.v[0] = a; f.v[1] = b; f.v[2] = c;
    f.nb[0] = f.nb[1] = f.nb[2] = -1;
    f.normal = bv_detail::normalize(bv_detail::cross(pts_[b] - pts_[a], pts_[c] - pts_[a]));
    f.offset = bv_detail::dot(f.normal, pts_[a]);
    faces_.push_back(std::move(f));
    return int(faces_.size()) - 1;
  }

  void build_tetrahedron(const int s[4]) {
    interior_ = (pts_[s[0]] + pts_[s[1]] + pts_[s[2]] + pts_[s[3]]) * 0.25;
    const int tri[4][3] = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
    const int opposite[4] = {3, 2, 0, 1};
    for (int t = 0; t < 4; ++t) {
      const int f = make_face(s[tri[t][0]], s[tri[t][1]], s[tri[t][2]]);
      if (distance(faces_[f], pts_[s[opposite[t]]]) > 0.0) {
        faces_.pop_back();
        make_face(s[tri[t][0]], s[tri[t][2]], s[tri[t][1]]);
      }
    }
    for (int f = 0; f < 4; ++f) {
      for (int e = 0; e < 3; ++e) {
        const int a = faces_[f].v[e], b = faces_[f].v[(e + 1) % 3];
        for (int g = 0; g < 4; ++g) {
          for (int k = 0; k < 3; ++k) {
            if (faces_[g].v[k] == b && faces_[g].v[(k + 1) % 3] == a) faces_[f].nb[e] = g;
          }
        }
      }
    }
    std::vector<int> all;
    for (int i = 0; i < int(pts_.size()); ++i) {
      if (i != s[0] && i != s[1] && i != s[2] && i != s[3]) all.push_back(i);
    }
    assign(all, 0, 4);
  }

  /// Gives each point to the first face in [first, last) it lies outside of; the others are inside and dropped.
  void assign(const std::vector<int>& points, int first, int last) {
    for (int i : points) {
      for (int f = first; f < last; ++f) {
        if (faces_[f].alive && distance(faces_[f], pts_[i]) > eps_) {
          faces_[f].outside.push_back(i);
          break;
        }
      }
    }
  }

  void add_point(int start, std::vector<int>& work) {
    Face& f0 = faces_[start];
    const auto far = std::max_element(f0.outside.begin(), f0.outside.end(), [&](int a, int b) {
      return distance(faces_[start], pts_[a]) < distance(faces_[start], pts_[b]);
    });
    const int apex = *far;
    f0.outside.erase(far);
    const Vec3d& p = pts_[apex];
    // The faces the apex sees, found from the start face across neighbor links; the horizon edges border them.
    ++stamp_;
    std::vector<int> visible{start}, stack{start};
    faces_[start].stamp = stamp_;
    struct Edge { int a, b, across; };
    std::vector<Edge> horizon;
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      for (int e = 0; e < 3; ++e) {
        const int g = faces_[f].nb[e];
        if (faces_[g].stamp == stamp_) continue;
        if (distance(faces_[g], p) > eps_) {
          faces_[g].stamp = stamp_;
          visible.push_back(g);
          stack.push_back(g);
        } else {
          horizon.push_back({faces_[f].v[e], faces_[f].v[(e + 1) % 3], g});
        }
      }
    }
    // A horizon that is not one simple loop means rounding made the visible region non-disk-like; the point is
    // then within a few tolerances of the hull and is left out.
    if (!simple_loop(horizon)) {
      work.push_back(start);
      return;
    }
    const int first_new = int(faces_.size());
    for (const Edge& e : horizon) {
      const int nf = make_face(e.a, e.b, apex);
      faces_[nf].nb[0] = e.across;
      Face& g = faces_[e.across];
      for (int k = 0; k < 3; ++k) {
        if (g.v[k] == e.b && g.v[(k + 1) % 3] == e.a) g.nb[k] = nf;
      }
      start_of_[e.a] = nf;
      end_of_[e.b] = nf;
    }
    for (int nf = first_new; nf < int(faces_.size()); ++nf) {
      faces_[nf].nb[1] = start_of_[faces_[nf].v[1]];
      faces_[nf].nb[2] = end_of_[faces_[nf].v[0]];
    }
    for (const Edge& e : horizon) start_of_[e.a] = -1;
    std::vector<int> orphans;
    for (int f : visible) {
      faces_[f].alive = false;
      orphans.insert(orphans.end(), faces_[f].outside.begin(), faces_[f].outside.end());
      faces_[f].outside.clear();
      faces_[f].outside.shrink_to_fit();
    }
    assign(orphans, first_new, int(faces_.size()));
    for (int nf = first_new; nf < int(faces_.size()); ++nf) work.push_back(nf);
  }

  template <class Edge>
  bool simple_loop(const std::vector<Edge>& horizon) {
    if (start_of_.empty()) {
      start_of_.assign(pts_.size(), -1);
      end_of_.assign(pts_.size(), -1);
    }
    bool ok = true;
    for (std::size_t i = 0; i < horizon.size(); ++i) {
      if (start_of_[horizon[i].a] != -1) ok = false;
      start_of_[horizon[i].a] = int(i);
    }
    if (ok) {
      std::size_t steps = 0;
      int at = horizon[0].b;
      while (steps < horizon.size() && at != horizon[0].a && start_of_[at] != -1) {
        at = horizon[start_of_[at]].b;
        ++steps;
      }
      ok = at == horizon[0].a && steps + 1 == horizon.size();
    }
    for (const Edge& e : horizon) start_of_[e.a] = -1;
    return ok;
  }

  std::vector<Vec3d> pts_;
  std::vector<Face> faces_;
  std::vector<int> start_of_, end_of_;  // new face by its horizon edge's first / second vertex
  Vec3d plane_normal_;
  Vec3d interior_;
  double eps_ = 0.0;
  int stamp_ = 0;
};

}  // namespace

HullMeasure convex_hull_measure(std::span<const Vec3> points) { return Quickhull(points).run().measure; }

ConvexHull bv_detail::convex_hull(std::span<const Vec3> points) { return Quickhull(points).run(); }

void TightnessSums::add(double bv_area, std::span<const Vec3> points, bool with_hull) {
  AABB box;
  for (const Vec3& p : points) box.extend(p);
  volume_area += bv_area;
  aabb_area += box.surface_area();
  if (with_hull) {
    hulled_volume_area += bv_area;
    hull_area += convex_hull_measure(points).area;
  }
  ++count;
}

}  // namespace rayaccel
