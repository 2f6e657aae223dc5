// The convex hull's faces for the volume fitters (the hull volume picks its planes among them); the same Quickhull
// that measures tightness (convex_hull.cpp).
#pragma once

#include <span>
#include <vector>

#include "fit_support.h"
#include "rayaccel/bv/tightness.h"

namespace rayaccel::bv_detail {

/// One face of a convex hull: outward unit normal and weight (area; for the in-plane edges of a flat hull, length).
struct HullFacet {
  Vec3d normal;
  double offset = 0.0;  ///< dot(normal, p) for the face's points (up to the hull's tolerance)
  double weight = 0.0;
  bool in_plane = false;  ///< an edge of a flat hull: its normal lies in the hull's plane
};

struct ConvexHull {
  HullMeasure measure;
  /// Triangles of a solid hull; for a flat one, both sides of its plane and the polygon's edges; empty for
  /// collinear, single and empty sets.
  std::vector<HullFacet> facets;
};

/// The convex hull's measure and faces by Quickhull (tolerance as convex_hull_measure).
ConvexHull convex_hull(std::span<const Vec3> points);

}  // namespace rayaccel::bv_detail
