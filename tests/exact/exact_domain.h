// The domain in which the library promises exact answers (README, "Exactness, and the range it holds for"), as a
// conservative predicate for checks of arbitrary (fuzzed) rays and scenes against the exact reference: finite rays
// and scenes in which the ray's sheared vertex coordinates stay in float range (in world units across the ray, in
// units of t along it), with subnormal direction components read as zero. Void rays are inside: they hit nothing,
// here and in the reference. Triangles with a NaN or infinite vertex are never hit (the reference skips them too),
// so they do not count against a ray. The test is written from the README's words, sharing no code with the kernels,
// and leaves a margin: when in doubt a ray is outside, and its answers are checked against brute force only.
#pragma once

#include "rayaccel/core/ray.h"
#include "rayaccel/core/primitives.h"

namespace rayaccel::exact {

/// Whether a ray's answers on a mesh can be checked against the exact reference, or why not.
enum class DomainVerdict {
  inside,
  coordinate_out_of_range,  ///< some vertex minus the origin exceeds 2^126 (the sheared coordinates may overflow)
  depth_out_of_range,       ///< some vertex depth in units of t, if not 0, lies outside [2^-100, 2^126]
};
const char* to_string(DomainVerdict verdict);

/// The ray as the README says every kernel reads it: direction components below FLT_MIN in magnitude are zero (of
/// their sign). Stated here again, apart from the library's own code for it, so that a fault there is caught.
Ray ray_as_read(const Ray& ray);

/// `inside` when the library guarantees `ray`'s answers on `mesh` as the exact reference computes them for
/// ray_as_read(ray). Checks every finite triangle: A = vertex - origin (in double) must satisfy |A_k| <= 2^126 on
/// every axis, so that the kernel's float A and its sheared coordinates A_x - (d_x / d_z) A_z stay finite; and each
/// vertex depth along a dominant axis of the direction, A_z / d_z in units of t, must be 0 or in [2^-100, 2^126],
/// so that t and its error bound neither overflow nor underflow (all dominant axes when components tie). A shear
/// d_x / d_z that underflows float is inside: the kernel bounds its absolute error (kShearAbsoluteError).
DomainVerdict exact_domain(const Ray& ray, const TriangleMesh& mesh);

}  // namespace rayaccel::exact
