// Capped hull fitting: Quickhull planes scored by how much of the box they cut away, near-parallel ones skipped,
// each moved out to the points' support for its stored float normal.
#include "rayaccel/bv/hull_volume.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "convex_hull.h"
#include "fit_support.h"
#include "polytope_area.h"
#include "rayaccel/core/error.h"
#include "rayaccel/core/float_rounding.h"

namespace rayaccel {
namespace {

using bv_detail::Vec3d;

/// Normals closer than this cosine (about 18 degrees) to a chosen one are skipped: they cut nearly the same corner.
constexpr double kParallelCosine = 0.95;
/// Planes cutting less than this fraction of the box's extent away add nothing worth a test.
constexpr double kMinCutFraction = 1e-6;

/// Support of the box along n: the largest dot(n, p) over its corners.
double box_support(const AABB& box, const Vec3d& n) {
  double s = 0.0;
  for (int a = 0; a < 3; ++a) s += std::max(n[a] * box.lo[a], n[a] * box.hi[a]);
  return s;
}

}  // namespace

HullVolume::HullVolume() {
  std::fill(std::begin(planes.normal_x), std::end(planes.normal_x), 0.0f);
  std::fill(std::begin(planes.normal_y), std::end(planes.normal_y), 0.0f);
  std::fill(std::begin(planes.normal_z), std::end(planes.normal_z), 0.0f);
  std::fill(std::begin(planes.offset), std::end(planes.offset), std::numeric_limits<float>::infinity());
}

HullVolume HullVolume::fit(std::span<const Vec3> points, int max_planes) {
  if (max_planes < 0 || max_planes > kMaxPlanes) {
    throw Error("hull volume: max_planes " + std::to_string(max_planes) + " is outside 0.." +
                std::to_string(kMaxPlanes));
  }
  HullVolume v;
  for (const Vec3& p : points) v.box.extend(p);
  if (points.empty()) return v;
  const bv_detail::ConvexHull hull = bv_detail::convex_hull(points);
  const Vec3d lo(v.box.lo), hi(v.box.hi);
  const double extent = (hi.x - lo.x) + (hi.y - lo.y) + (hi.z - lo.z);
  struct Scored {
    Vec3d normal;
    double score;
  };
  std::vector<Scored> candidates;
  for (const bv_detail::HullFacet& f : hull.facets) {
    // Only the ranking uses the face's own offset; the stored plane is moved to the points' support below.
    const double depth = box_support(v.box, f.normal) - f.offset;
    if (!(depth > kMinCutFraction * extent)) continue;
    const bool flat_side = hull.measure.volume == 0.0 && !f.in_plane;
    candidates.push_back({f.normal, flat_side ? std::numeric_limits<double>::infinity() : f.weight * depth});
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Scored& a, const Scored& b) { return a.score > b.score; });
  const Vec3 c = hull_reference_point(v.box);
  const Vec3d cd(c);
  // Double rounding of the support (products and sums of floats, relative 2^-53 each) stays far below this margin.
  const double margin = 0x1p-48 * extent;
  std::vector<Vec3d> chosen;
  for (const Scored& s : candidates) {
    if (v.plane_count == std::uint32_t(max_planes)) break;
    const bool parallel = std::any_of(chosen.begin(), chosen.end(),
                                      [&](const Vec3d& n) { return bv_detail::dot(n, s.normal) > kParallelCosine; });
    if (parallel) continue;
    chosen.push_back(s.normal);
    const int lane = static_cast<int>(v.plane_count++);
    const Vec3 normal = bv_detail::to_float(s.normal);
    v.planes.normal_x[lane] = normal.x;
    v.planes.normal_y[lane] = normal.y;
    v.planes.normal_z[lane] = normal.z;
    const Vec3d n(normal);
    double support = -std::numeric_limits<double>::infinity();
    for (const Vec3& p : points) support = std::max(support, bv_detail::dot(n, Vec3d(p) - cd));
    v.planes.offset[lane] = round_up_to_float(support + margin);
  }
  return v;
}

float HullVolume::surface_area() const {
  if (is_empty()) return 0.0f;
  std::vector<bv_detail::Halfspace> cuts;
  const Vec3d c(hull_reference_point(box));
  for (std::uint32_t i = 0; i < plane_count; ++i) {
    const Vec3d n(planes.normal(int(i)));
    cuts.push_back({n, double(planes.offset[i]) + bv_detail::dot(n, c)});
  }
  return static_cast<float>(bv_detail::polytope_area(box, cuts));
}

bool HullVolume::contains(const Vec3& p) const {
  if (is_empty()) return false;
  const Vec3 c = hull_reference_point(box);
  const Vec3 e = box.hi - box.lo;
  const double scale = double(max_component(abs(c))) + 0.5 * (double(e.x) + e.y + e.z);
  const double tolerance = 4.0 * 0x1p-24 * scale;
  for (int a = 0; a < 3; ++a) {
    if (!(p[a] >= box.lo[a] - tolerance && p[a] <= box.hi[a] + tolerance)) return false;
  }
  const Vec3d d = Vec3d(p) - Vec3d(c);
  for (std::uint32_t i = 0; i < plane_count; ++i) {
    if (!(bv_detail::dot(Vec3d(planes.normal(int(i))), d) <= double(planes.offset[i]) + tolerance)) return false;
  }
  return true;
}

}  // namespace rayaccel
