// The independent reference for ray/triangle answers: exact rational arithmetic (GMP) on the float inputs, sharing
// no code and no rule with the library's kernels. A triangle is hit when the ray o + t d meets it (edges and
// vertices included) at t_min < t <= t_max, found by Cramer's rule on o + t d = v0 + b (v1 - v0) + g (v2 - v0)
// (no sheared frame, no edge functions); a ray in the triangle's plane, or a triangle of zero area, is never hit.
// A double-precision pass with a generous error bound only skips triangles that the ray misses by far.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel::exact {

/// One triangle the ray hits exactly: its exact t (and barycentrics), rounded to double.
struct ExactHit {
  std::uint32_t prim_id;
  double t, u, v;
  /// The t error the library guarantees for this triangle and ray (README, "Exactness"): 1/32 of the triangle's
  /// depth range along the ray plus 2^-18 of its farthest vertex distance, in units of t.
  double t_tolerance;
};

class ExactReference {
 public:
  explicit ExactReference(const TriangleMesh& mesh);
  /// Every triangle the ray hits with t > t_min, whatever t_max, by increasing t (the checks below need the hits
  /// just past t_max). Void rays (NaN, Inf, zero direction, t_min > t_max) hit nothing.
  std::vector<ExactHit> hits_past_t_min(const Ray& ray) const;

  /// Empty when `hit` (a structure's closest hit for `ray`, whose exact hits_past_t_min() are `exact`) is what the
  /// library guarantees, else what is wrong: the primitive is hit exactly with t_min < t <= t_max (t_max widened by
  /// its tolerance), its t within its tolerance, and no other hit closer by more than both tolerances; a miss only
  /// when every exact hit lies within its tolerance of t_min or t_max.
  static std::string closest_hit_mismatch(const Ray& ray, const std::vector<ExactHit>& exact, const Hit& hit);
  /// The same for an any-hit answer.
  static std::string occlusion_mismatch(const Ray& ray, const std::vector<ExactHit>& exact, bool occluded);

 private:
  std::vector<std::array<Vec3, 3>> triangles_;
};

}  // namespace rayaccel::exact
