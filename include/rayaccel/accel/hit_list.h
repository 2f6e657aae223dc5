// HitList: the crossings of one ray with a triangle scene for all-hits queries, each crossing counted once also
// through edges and vertices (geometry/crossing.h).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/geometry/crossing.h"
#include "rayaccel/geometry/ray_triangle.h"

namespace rayaccel {

class HitList {
 public:
  /// Collects into `hits` (cleared first), which is also the result's storage.
  HitList(const PreparedRay& ray, std::vector<Hit>& hits) : ray_(ray), hits_(hits) { hits_.clear(); }

  const PreparedRay& ray() const { return ray_; }

  /// Tests one candidate triangle over the ray's whole interval.
  void test(std::uint32_t prim_id, const Vec3& v0, const Vec3& v1, const Vec3& v2) {
    Hit hit = Hit::begin(ray_);
    if (intersect_triangle(ray_, v0, v1, v2, prim_id, hit) && counts_as_crossing(ray_, v0, v1, v2)) {
      hits_.push_back(hit);
    }
  }

  /// Sorts the crossings by t (equal t: by primitive id), keeps each primitive once (a structure with spatial splits
  /// or pre-split triangles reaches one primitive from several leaves, always with the same hit), trims to the
  /// `max_hits` nearest and returns how many crossings there were before trimming.
  std::size_t finish(std::size_t max_hits) {
    std::sort(hits_.begin(), hits_.end(), [](const Hit& a, const Hit& b) {
      return a.t < b.t || (a.t == b.t && a.prim_id < b.prim_id);
    });
    hits_.erase(std::unique(hits_.begin(), hits_.end(),
                            [](const Hit& a, const Hit& b) { return a.prim_id == b.prim_id && a.t == b.t; }),
                hits_.end());
    const std::size_t count = hits_.size();
    if (count > max_hits) hits_.resize(max_hits);
    return count;
  }

 private:
  const PreparedRay& ray_;
  std::vector<Hit>& hits_;
};

}  // namespace rayaccel
