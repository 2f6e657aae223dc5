// Sampling for secondary rays: counter-based random numbers (a SplitMix64 finalizer over seed, index and dimension;
// Steele, Lea, Flood 2014), an orthonormal basis from one vector (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited") and cosine-weighted hemisphere directions (Malley's method: uniform disk lifted to the hemisphere).
#pragma once

#include <cstdint>

#include "rayaccel/core/vec3.h"

namespace rayaccel {

/// A 64-bit hash of (seed, index, dimension); a pure function, so the value for a ray index never depends on
/// which thread computes it.
std::uint64_t hash_counter(std::uint64_t seed, std::uint64_t index, std::uint32_t dimension);
/// Uniform float in [0, 1) (24 random bits) from hash_counter().
float uniform_float(std::uint64_t seed, std::uint64_t index, std::uint32_t dimension);

/// Unit t and b such that (t, b, n) is a right-handed orthonormal basis; n must be unit length.
void orthonormal_basis(const Vec3& n, Vec3& t, Vec3& b);

/// Unit direction with density cos(theta) / pi about the unit normal n, from uniforms u1, u2 in [0, 1).
/// cos(theta) >= 2^-12 > 0: the direction is never tangent to the surface.
Vec3 cosine_hemisphere(const Vec3& n, float u1, float u2);

}  // namespace rayaccel
