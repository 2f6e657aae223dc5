// Exact front-to-back visibility inside a cone's cross-section: the union of projected convex polygons (triangles
// clipped and projected by cone_coverage.h), grown one polygon at a time nearest first, with the solid angle each adds,
// by Green's theorem over the union's boundary (the polygons' edges outside all others) restricted to the disk.
#pragma once

#include <span>
#include <vector>

#include "rayaccel/generalized/cone_coverage.h"

namespace rayaccel::generalized {

class ProjectedUnion {
 public:
  /// An empty union inside the cone of this half-angle (radians, in (0, pi / 2)).
  explicit ProjectedUnion(double half_angle);

  /// Adds a convex polygon (either orientation; fewer than 3 points or zero area add nothing) and returns the solid
  /// angle inside the cone it newly covers: its part outside the polygons added before. Edges shared by two polygons
  /// (the projections of a mesh's shared edges) are resolved exactly: opposite directions (neighbours on either
  /// side) leave the union's boundary, equal directions (a fold, as a closed mesh's front and back faces at its
  /// silhouette) stay once. Exact up to rounding otherwise.
  double add(std::span<const PlanePoint> polygon);

 private:
  /// A piece [t0, t1] of the directed edge a -> b of polygon `owner` (oriented counter-clockwise).
  struct Piece {
    PlanePoint a, b;
    double t0, t1;
  };
  struct Polygon {
    std::vector<PlanePoint> points;  ///< counter-clockwise
    PlanePoint lo, hi;               ///< bounding box
  };
  double half_angle_;
  std::vector<Polygon> polygons_;
  std::vector<Piece> boundary_;                     ///< the union's boundary, each piece outside every polygon
};

}  // namespace rayaccel::generalized
