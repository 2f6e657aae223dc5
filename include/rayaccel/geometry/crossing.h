// Which hits of the watertight test are surface crossings, so that a ray through an edge or vertex counts each
// crossing once: simulation of simplicity (Edelsbrunner & Muecke 1990) in the sheared frame of Woop et al. 2013.
#pragma once

#include "rayaccel/core/ray.h"
#include "rayaccel/core/vec3.h"

namespace rayaccel {

/// For a triangle that intersect_triangle() reports hit by `ray` (not void): true when the ray moved by (eps, eps^2)
/// in its sheared (x, y) still meets the triangle's interior, i.e. the hit is the one counted for its crossing. A hit
/// strictly inside the triangle always counts; one on an edge or vertex counts in exactly one of the triangles met
/// there when the ray crosses the surface, and in none or two when it only touches it.
bool counts_as_crossing(const PreparedRay& ray, const Vec3& v0, const Vec3& v1, const Vec3& v2);

}  // namespace rayaccel
