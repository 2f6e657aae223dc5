// The union of projected convex polygons inside a cone, grown front to back (Green's theorem over its boundary).
#include "rayaccel/generalized/cone_union.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace rayaccel::generalized {

namespace {

/// Twice the signed area.
double signed_area(std::span<const PlanePoint> poly) {
  double sum = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) sum += cross2(poly[i], poly[(i + 1) % poly.size()]);
  return sum;
}

/// The open interval of t in (lo, hi) where a + t (b - a) is inside the counter-clockwise convex polygon, as a pair
/// (empty when first >= second). A segment lying on one of the polygon's edge lines counts as inside when it runs
/// against the edge (the polygons are neighbours across it), or along it and `along_inside` (the polygon was added
/// first, so its copy of a fold's edge is the one kept).
std::pair<double, double> inside(const PlanePoint& a, const PlanePoint& b, std::span<const PlanePoint> poly,
                                 bool along_inside) {
  double lo = 0.0, hi = 1.0;
  const PlanePoint d{b.x - a.x, b.y - a.y};
  for (std::size_t i = 0; i < poly.size() && lo < hi; ++i) {
    const PlanePoint& p = poly[i];
    const PlanePoint& q = poly[(i + 1) % poly.size()];
    const PlanePoint e{q.x - p.x, q.y - p.y};
    // Side of a + t d relative to p -> q: f0 + t f1, positive inside.
    const double f0 = cross2(e, PlanePoint{a.x - p.x, a.y - p.y});
    const double f1 = cross2(e, d);
    // On the edge's line up to rounding (relative 1e-9: projections of collinear 3D edges, such as a crease where
    // two faces meet with different vertices, are collinear only up to rounding): decided by direction, not by sign.
    const double l1e = std::fabs(e.x) + std::fabs(e.y);
    const double reach = l1e * (std::fabs(a.x - p.x) + std::fabs(a.y - p.y) + std::fabs(d.x) + std::fabs(d.y));
    if (std::fabs(f1) <= 1e-9 * reach && std::fabs(f0) <= 1e-9 * reach) {
      const bool against = e.x * d.x + e.y * d.y < 0.0;
      if (against || along_inside) continue;
      return {1.0, 0.0};
    }
    if (f1 == 0.0) {
      if (f0 > 0.0) continue;
      return {1.0, 0.0};
    }
    const double t = -f0 / f1;
    if (f1 > 0.0) {
      lo = std::max(lo, t);
    } else {
      hi = std::min(hi, t);
    }
  }
  return {lo, hi};
}

/// Whether the boxes [lo, hi] and the segment's box overlap (touching counts, so shared edges are always tested).
bool boxes_meet(const PlanePoint& lo, const PlanePoint& hi, const PlanePoint& a, const PlanePoint& b) {
  return std::max(a.x, b.x) >= lo.x && std::min(a.x, b.x) <= hi.x && std::max(a.y, b.y) >= lo.y &&
         std::min(a.y, b.y) <= hi.y;
}

}  // namespace

ProjectedUnion::ProjectedUnion(double half_angle) : half_angle_(half_angle) {}

double ProjectedUnion::add(std::span<const PlanePoint> polygon) {
  if (polygon.size() < 3) return 0.0;
  const double area = signed_area(polygon);
  if (!(area != 0.0)) return 0.0;
  Polygon shape{{polygon.begin(), polygon.end()}, polygon[0], polygon[0]};
  std::vector<PlanePoint>& poly = shape.points;
  if (area < 0.0) std::reverse(poly.begin(), poly.end());
  for (const PlanePoint& p : poly) {
    shape.lo = {std::min(shape.lo.x, p.x), std::min(shape.lo.y, p.y)};
    shape.hi = {std::max(shape.hi.x, p.x), std::max(shape.hi.y, p.y)};
  }
  const auto piece_angle = [&](const Piece& s) {
    const PlanePoint d{s.b.x - s.a.x, s.b.y - s.a.y};
    return segment_solid_angle({s.a.x + s.t0 * d.x, s.a.y + s.t0 * d.y}, {s.a.x + s.t1 * d.x, s.a.y + s.t1 * d.y},
                               half_angle_);
  };
  // Cuts `pieces` by the polygon's inside interval in place: the parts inside go to `cut` (when given), the rest stay.
  const auto subtract = [](std::vector<Piece>& pieces, const Polygon& by, bool along_inside, std::vector<Piece>* cut) {
    const std::size_t count = pieces.size();
    bool removed = false;
    for (std::size_t i = 0; i < count; ++i) {
      Piece& s = pieces[i];
      if (!boxes_meet(by.lo, by.hi, s.a, s.b)) continue;
      auto [lo, hi] = inside(s.a, s.b, by.points, along_inside);
      lo = std::max(lo, s.t0);
      hi = std::min(hi, s.t1);
      if (!(lo < hi)) continue;
      if (cut) cut->push_back({s.a, s.b, lo, hi});
      const Piece whole = s;
      if (whole.t0 < lo) {
        s.t1 = lo;
        if (hi < whole.t1) pieces.push_back({whole.a, whole.b, hi, whole.t1});  // may move s: not used after
      } else if (hi < whole.t1) {
        s.t0 = hi;
      } else {
        s.t1 = s.t0;  // emptied, erased below
        removed = true;
      }
    }
    if (removed) std::erase_if(pieces, [](const Piece& s) { return !(s.t0 < s.t1); });
  };
  double added = 0.0;
  // The new polygon's edges outside every earlier polygon join the boundary.
  std::vector<Piece> fresh;
  for (std::size_t i = 0; i < poly.size(); ++i) fresh.push_back({poly[i], poly[(i + 1) % poly.size()], 0.0, 1.0});
  for (const auto& earlier : polygons_) {
    if (fresh.empty()) break;
    if (boxes_meet(earlier.lo, earlier.hi, shape.lo, shape.hi)) subtract(fresh, earlier, true, nullptr);
  }
  for (const Piece& s : fresh) added += piece_angle(s);
  // The old boundary inside the new polygon leaves it.
  std::vector<Piece> covered;
  subtract(boundary_, shape, false, &covered);
  for (const Piece& s : covered) added -= piece_angle(s);
  boundary_.insert(boundary_.end(), fresh.begin(), fresh.end());
  polygons_.push_back(std::move(shape));
  return std::max(added, 0.0);
}

}  // namespace rayaccel::generalized
