// The independent reference of the double path's tests: exact rational arithmetic (GMP) on the double inputs, as
// tests/exact does for float, sharing no code and no rule with the library's kernels. A triangle is hit when the ray
// o + t d meets it (edges and vertices included) at t > t_min, by Cramer's rule on o + t d = v0 + b e1 + g e2; a ray
// in the triangle's plane, or a triangle of zero area, is never hit. A double pass only skips triangles the ray's
// line misses by far (a barycentric below zero by 1e-9 of its terms).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "rayaccel/core/ray_d.h"

namespace rayaccel::exact_d {

/// One triangle the ray hits exactly: its exact t and barycentrics, rounded to double.
struct ExactHitD {
  std::uint32_t prim_id;
  double t, u, v;
};

/// Every triangle of `triangles` the ray hits with t > ray.t_min (t_max ignored), by increasing t. A void ray (NaN,
/// infinite or zero direction) hits nothing.
std::vector<ExactHitD> exact_hits(const std::vector<std::array<DVec3, 3>>& triangles, const RayD& ray);

}  // namespace rayaccel::exact_d
