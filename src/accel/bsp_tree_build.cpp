// BSP tree build (Ize, Wald & Parker 2008): per node, candidate planes along 13 k-DOP directions at the
// references' extents (binned for large nodes) and the triangles' own planes, scored by SAH over the surface areas
// of the two clipped cell polytopes; references are triangles clipped to their cells.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "rayaccel/accel/bsp_tree.h"
#include "rayaccel/core/error.h"
#include "rayaccel/geometry/clip_polygon.h"

namespace rayaccel {

namespace {

/// A primitive reference in a cell: for a triangle, the part of it inside the cell (a convex polygon); for other
/// primitives, the 8 corners of the box (never clipped).
struct Ref {
  std::uint32_t prim;
  std::vector<Vec3> points;
};

/// The projection of a reference on a plane normal, [lo, hi], and the classification tolerance: a reference
/// within `tolerance` of a plane counts on both sides, so rounding never drops it from a cell.
struct Extent {
  double lo, hi, tolerance;
  bool reaches_below(double d) const { return lo - tolerance <= d; }
  bool reaches_above(double d) const { return hi + tolerance >= d; }
};

Extent project(const Ref& r, const Vec3& n, double tolerance) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Vec3& p : r.points) {
    const double s = double(n.x) * p.x + double(n.y) * p.y + double(n.z) * p.z;
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  return {lo, hi, tolerance};
}

struct Plane {
  Vec3 normal;
  float offset = 0.0f;
};

struct Candidate {
  double cost = std::numeric_limits<double>::infinity();
  Plane plane;
};

class BspBuilder {
 public:
  BspBuilder(const Scene& scene, const BspTreeOptions& options, int max_depth, double tolerance)
      : scene_(scene), options_(options), max_depth_(max_depth), tolerance_(tolerance) {}

  void build(BspTreeData& out, std::vector<Ref> refs, const Polytope& cell, double root_area, int depth) {
    if (out.nodes.size() > BspNode::kMaxField) throw Error("bsp: more nodes than the 31-bit child index holds");
    const auto node = static_cast<std::uint32_t>(out.nodes.size());
    out.nodes.emplace_back();
    const std::size_t n = refs.size();
    const double area = cell.surface_area();
    const double weight = root_area > 0.0 ? area / root_area : 1.0;
    const double leaf_cost = double(options_.intersection_cost) * double(n);
    Candidate best;
    if (n > std::size_t(options_.leaf_size) && depth < max_depth_ && area > 0.0) best = find_split(refs, cell, area);
    if (!(best.cost < leaf_cost)) {
      out.sah_cost += weight * leaf_cost;
      out.nodes[node] = BspNode::leaf(static_cast<std::uint32_t>(out.prim_indices.size()),
                                      static_cast<std::uint32_t>(n));
      for (const Ref& r : refs) out.prim_indices.push_back(r.prim);
      return;
    }
    out.sah_cost += weight * options_.traversal_cost;
    const Plane& h = best.plane;
    std::vector<Ref> below, above;
    for (Ref& r : refs) {
      const Extent e = project(r, h.normal, tolerance_);
      const bool is_below = e.reaches_below(h.offset), is_above = e.reaches_above(h.offset);
      if (is_below && is_above && is_triangle()) {
        below.push_back(clipped(r, h, true));
        above.push_back(clipped(r, h, false));
      } else if (is_below && is_above) {
        below.push_back(r);
        above.push_back(std::move(r));
      } else if (is_below) {
        below.push_back(std::move(r));
      } else {
        above.push_back(std::move(r));
      }
    }
    refs = {};
    const Polytope below_cell = cell.clip(h.normal, h.offset, true);
    build(out, std::move(below), below_cell, root_area, depth + 1);
    const auto above_node = static_cast<std::uint32_t>(out.nodes.size());
    out.nodes[node] = BspNode::interior(h.normal, h.offset, above_node);
    build(out, std::move(above), cell.clip(h.normal, h.offset, false), root_area, depth + 1);
  }

 private:
  bool is_triangle() const { return scene_.kind() == PrimitiveKind::triangles; }

  /// The part of a straddling triangle on one side, clipped against the plane moved outward by the
  /// classification tolerance; the whole polygon if clipping leaves nothing (it touched only within tolerance).
  Ref clipped(const Ref& r, const Plane& h, bool keep_below) const {
    Ref out{r.prim, std::vector<Vec3>(clip_capacity(r.points.size()))};
    const int k = keep_below ? clip_polygon_to_halfspace(r.points.data(), int(r.points.size()), h.normal,
                                                         double(h.offset) + tolerance_, out.points.data())
                             : clip_polygon_to_halfspace(r.points.data(), int(r.points.size()), -h.normal,
                                                         -(double(h.offset) - tolerance_), out.points.data());
    if (k == 0) return r;
    out.points.resize(std::size_t(k));
    return out;
  }

  /// SAH cost of a plane given the counts on each side.
  void consider(const Polytope::Slicer& slicer, double area, const Plane& h, std::size_t n, std::size_t n_below,
                std::size_t n_above, Candidate& best) const {
    if (n_below == n && n_above == n) return;  // no progress
    double a_below = 0.0, a_above = 0.0;
    slicer.split_areas(h.offset, a_below, a_above);
    const double cost = options_.traversal_cost + options_.intersection_cost *
                                                      (a_below / area * double(n_below) + a_above / area * double(n_above));
    if (cost < best.cost) best = {cost, h};
  }

  /// Candidates along one fixed direction: planes at the references' extents (small nodes) or at 15 evenly spaced
  /// offsets across the cell (large nodes), counted from the sorted extents.
  void sweep_direction(const std::vector<Ref>& refs, const Polytope& cell, double area, const Vec3& dir,
                       Candidate& best) {
    const std::size_t n = refs.size();
    los_.clear();
    his_.clear();
    for (const Ref& r : refs) {
      const Extent e = project(r, dir, tolerance_);
      los_.push_back(e.lo - e.tolerance);
      his_.push_back(e.hi + e.tolerance);
    }
    positions_.clear();
    if (n <= std::size_t(options_.exact_threshold)) {
      // Just outside each reference's tolerance band, so the plane leaves that reference on one side.
      for (std::size_t i = 0; i < n; ++i) {
        positions_.push_back(static_cast<float>(los_[i] - tolerance_));
        positions_.push_back(static_cast<float>(his_[i] + tolerance_));
      }
    } else {
      double lo = 0.0, hi = 0.0;
      cell.extent(dir, lo, hi);
      constexpr int kBins = 16;
      for (int k = 1; k < kBins; ++k) positions_.push_back(static_cast<float>(lo + (hi - lo) * k / kBins));
    }
    std::sort(los_.begin(), los_.end());
    std::sort(his_.begin(), his_.end());
    std::sort(positions_.begin(), positions_.end());
    positions_.erase(std::unique(positions_.begin(), positions_.end()), positions_.end());
    const Polytope::Slicer slicer(cell, dir);
    for (float d : positions_) {
      const auto n_below = std::size_t(std::upper_bound(los_.begin(), los_.end(), double(d)) - los_.begin());
      const auto n_above = std::size_t(his_.end() - std::lower_bound(his_.begin(), his_.end(), double(d)));
      consider(slicer, area, {dir, d}, n, n_below, n_above, best);
    }
  }

  /// A triangle's own supporting plane, if it has one (zero-area triangles have none).
  bool own_plane(std::uint32_t prim, Plane& h) const {
    const auto& t = scene_.triangle(prim);
    const double e1[3] = {double(t[1].x) - t[0].x, double(t[1].y) - t[0].y, double(t[1].z) - t[0].z};
    const double e2[3] = {double(t[2].x) - t[0].x, double(t[2].y) - t[0].y, double(t[2].z) - t[0].z};
    const double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double len = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    if (!(len > 0.0) || !std::isfinite(len)) return false;
    h.normal = Vec3{float(c[0] / len), float(c[1] / len), float(c[2] / len)};
    h.offset = static_cast<float>(double(h.normal.x) * t[0].x + double(h.normal.y) * t[0].y +
                                  double(h.normal.z) * t[0].z);
    return true;
  }

  Candidate find_split(const std::vector<Ref>& refs, const Polytope& cell, double area) {
    Candidate best;
    for (const Vec3& dir : kdop13_directions()) sweep_direction(refs, cell, area, dir, best);
    if (!options_.own_planes || !is_triangle()) return best;
    const std::size_t n = refs.size();
    const std::size_t samples = n <= std::size_t(options_.exact_threshold) ? n : 8;
    for (std::size_t s = 0; s < samples; ++s) {
      Plane h;
      if (!own_plane(refs[s * n / samples].prim, h)) continue;
      std::size_t n_below = 0, n_above = 0;
      for (const Ref& r : refs) {
        const Extent e = project(r, h.normal, tolerance_);
        n_below += e.reaches_below(h.offset) ? 1 : 0;
        n_above += e.reaches_above(h.offset) ? 1 : 0;
      }
      consider(Polytope::Slicer(cell, h.normal), area, h, n, n_below, n_above, best);
    }
    return best;
  }

  const Scene& scene_;
  const BspTreeOptions& options_;
  int max_depth_;
  double tolerance_;
  std::vector<double> los_, his_;
  std::vector<float> positions_;
};

}  // namespace

BspTreeData build_bsp_tree(const Scene& scene, const BspTreeOptions& options) {
  BspTreeData out;
  const PrimRefs prim_refs = scene.build_references();
  for (const PrimRef& r : prim_refs) out.bounds.extend(r.bounds);
  const std::size_t n = prim_refs.size();
  out.max_depth = split_tree_depth_limit(options.max_depth, n);
  if (n == 0) return out;
  std::vector<Ref> refs;
  refs.reserve(n);
  for (const PrimRef& r : prim_refs) {
    Ref ref{r.prim_id, {}};
    if (scene.kind() == PrimitiveKind::triangles) {
      const auto& t = scene.triangle(r.prim_id);
      ref.points.assign(t.begin(), t.end());
    } else {
      const AABB& b = r.bounds;
      for (int c = 0; c < 8; ++c) {
        ref.points.push_back({(c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z});
      }
    }
    refs.push_back(std::move(ref));
  }
  const Polytope root = Polytope::from_box(out.bounds);
  // One absolute tolerance for the whole tree, 2^-21 of the largest coordinate magnitude: far above the rounding
  // of any projection or clipped vertex, and the same at every node (a tolerance relative to each clipped polygon
  // would shrink with it, and validate() could not reproduce the builder's decisions).
  for (int a = 0; a < 3; ++a) {
    out.tolerance = std::max(out.tolerance, 0x1p-21 * std::max(std::fabs(double(out.bounds.lo[a])),
                                                                std::fabs(double(out.bounds.hi[a]))));
  }
  BspBuilder builder(scene, options, out.max_depth, out.tolerance);
  builder.build(out, std::move(refs), root, root.surface_area(), 0);
  return out;
}

}  // namespace rayaccel
