// ClosestPointSearch: the state of a branch-and-bound closest-point query (the best triangle so far and the bound it
// sets), which every structure's traversal drives: it skips a node whose box lies farther than the best distance
// and tests the triangles of the leaves it reaches (geometry/point_triangle.h, Ericson 2005, 5.1.5).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/closest_point.h"
#include "rayaccel/core/hit.h"
#include "rayaccel/core/vec3.h"
#include "rayaccel/geometry/point_triangle.h"

namespace rayaccel {

class ClosestPointSearch {
 public:
  /// Searches within `max_distance` of `point` (both checked by the caller: finite point, max_distance >= 0).
  ClosestPointSearch(const Vec3& point, float max_distance)
      : point_(point), best_squared_(double(max_distance) * double(max_distance)) {}

  const Vec3& point() const { return point_; }

  /// A lower bound on the squared distance, as closest_point_on_triangle() computes it, from the query point to
  /// anything inside `box`. The gap per axis is shrunk by 2^-30 of the coordinates' magnitude, far more than the
  /// double rounding of the triangle distances, so a box is never skipped that holds a triangle whose computed
  /// distance ties or beats the best: every structure then finds the same distance as brute force, bit for bit.
  double box_lower_bound(const AABB& box) const {
    double sum = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double p = point_[a], lo = box.lo[a], hi = box.hi[a];
      double gap = p < lo ? lo - p : (p > hi ? p - hi : 0.0);
      if (gap > 0.0) gap = std::max(0.0, gap - 0x1p-30 * (std::fabs(p) + std::max(std::fabs(lo), std::fabs(hi))));
      sum += gap * gap;
    }
    return sum;
  }
  /// True when something at squared distance `lower_bound` could still be the answer.
  bool may_improve(double lower_bound) const { return lower_bound <= best_squared_; }

  /// Tests one triangle; a closer one replaces the best (of equal distances the first tested is kept).
  void test(std::uint32_t prim_id, const Vec3& v0, const Vec3& v1, const Vec3& v2) {
    const TrianglePoint t = closest_point_on_triangle(point_, v0, v1, v2);
    if (t.distance_squared < best_squared_ || (prim_id_ == kInvalidPrimId && t.distance_squared == best_squared_)) {
      best_squared_ = t.distance_squared;
      best_ = t;
      prim_id_ = prim_id;
    }
  }

  ClosestPoint result() const {
    ClosestPoint out;
    if (prim_id_ == kInvalidPrimId) return out;
    out.point = Vec3{float(best_.x), float(best_.y), float(best_.z)};
    out.distance = float(std::sqrt(best_.distance_squared));
    out.prim_id = prim_id_;
    out.u = float(best_.u);
    out.v = float(best_.v);
    return out;
  }

 private:
  Vec3 point_;
  double best_squared_;
  TrianglePoint best_;
  std::uint32_t prim_id_ = kInvalidPrimId;
};

}  // namespace rayaccel
