// Which hits of the watertight test are surface crossings, so that a ray through an edge or vertex counts each
// crossing once: simulation of simplicity (Edelsbrunner & Muecke 1990) in the sheared frame of Woop et al. 2013.
#pragma once

#include "rayaccel/core/ray.h"
#include "rayaccel/core/vec3.h"

namespace rayaccel {

// Which hits of the watertight test are surface crossings: a ray through an edge or a vertex of a mesh hits every
// triangle around it (edges count as inside), so counting hits would count one crossing several times. Simulation of
// simplicity (Edelsbrunner & Mücke 1990, "Simulation of Simplicity", ACM TOG 9(1)) settles it: the ray is moved by
// the infinitesimal (eps, eps^2) in its sheared frame (the x, y of the watertight test, Woop et al. 2013), and a hit
// counts when the moved ray still meets the triangle's interior. The moved ray passes through no edge, vertex or
// triangle plane, so it meets a closed mesh (every edge shared by an even number of triangles) an even number of times,
// and each crossing of the original ray is counted exactly once, whatever the triangles' order or orientation. All
// signs are exact for the float inputs (exact_edge.h and an exact sum of products), so the two triangles of a shared
// edge always take opposite sides of the tie.

/// For a triangle that intersect_triangle() reports hit by `ray` (not void): true when the ray moved by (eps, eps^2)
/// in its sheared (x, y) still meets the triangle's interior, i.e. the hit is the one counted for its crossing. A hit
/// strictly inside the triangle always counts; one on an edge or vertex counts in exactly one of the triangles met
/// there when the ray crosses the surface, and in none or two when it only touches it.
bool counts_as_crossing(const PreparedRay& ray, const Vec3& v0, const Vec3& v1, const Vec3& v2);

}  // namespace rayaccel
