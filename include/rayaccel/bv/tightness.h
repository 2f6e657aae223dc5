// Tightness of bounding volumes: a volume's surface area against two references for the same points, their AABB
// (an upper reference) and their convex hull (the lower bound of every convex volume). The hull is an exact
// Quickhull (Barber, Dobkin, Huhdanpaa 1996, "The Quickhull Algorithm for Convex Hulls").
#pragma once

#include <cstddef>
#include <span>

#include "rayaccel/bv/bounding_volume.h"

namespace rayaccel {

/// Area and volume of a point set's convex hull. A flat set (all points within rounding of one plane) has twice
/// its polygon's area, like a flat AABB, and volume 0; collinear, single and empty sets have area 0.
struct HullMeasure {
  double area = 0.0;
  double volume = 0.0;
};

/// The convex hull's measure by Quickhull in double precision, with a distance tolerance of 1e-11 of the points'
/// scale (points nearer than that to a face count as on it). O(n log n) expected.
HullMeasure convex_hull_measure(std::span<const Vec3> points);

/// Running sums for a structure's tightness report: "mean volume area / mean AABB area" and "/ mean convex hull
/// area", over the nodes (point sets) added.
struct TightnessSums {
  double volume_area = 0.0;
  double aabb_area = 0.0;
  double hull_area = 0.0;
  double hulled_volume_area = 0.0;  ///< volume areas of the nodes added with their hull
  std::size_t count = 0;

  /// Adds one node: the area of its bounding volume and the points it encloses. with_hull = false leaves the node
  /// out of the hull ratio, for callers that cannot afford the hull on large nodes.
  void add(double bv_area, std::span<const Vec3> points, bool with_hull = true);
  /// Mean volume area over mean AABB area (1 for the AABB itself; 0 when nothing was added).
  double over_aabb() const { return aabb_area > 0.0 ? volume_area / aabb_area : 0.0; }
  /// Mean volume area over mean convex hull area (>= 1 for any convex enclosing volume; 0 when unknown).
  double over_hull() const { return hull_area > 0.0 ? hulled_volume_area / hull_area : 0.0; }
};

/// Fits BV to the points and returns its tightness sums (one node).
template <BoundingVolume BV>
TightnessSums tightness_of(std::span<const Vec3> points) {
  TightnessSums sums;
  sums.add(BV::fit(points).surface_area(), points);
  return sums;
}

}  // namespace rayaccel
