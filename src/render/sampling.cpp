// Counter-based random numbers, orthonormal basis (Duff et al. 2017) and cosine-weighted hemisphere sampling.
#include "rayaccel/render/sampling.h"

#include <cmath>
#include <numbers>

namespace rayaccel {

namespace {

/// SplitMix64's output function: a bijective mix of all 64 bits.
std::uint64_t mix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

std::uint64_t hash_counter(std::uint64_t seed, std::uint64_t index, std::uint32_t dimension) {
  return mix64(mix64(mix64(seed) ^ index) ^ dimension);
}

float uniform_float(std::uint64_t seed, std::uint64_t index, std::uint32_t dimension) {
  return static_cast<float>(hash_counter(seed, index, dimension) >> 40) * 0x1p-24f;
}

void orthonormal_basis(const Vec3& n, Vec3& t, Vec3& b) {
  // Branch-free in the sign of n.z: no singularity at n = (0, 0, -1), unlike Frisvad's original.
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

Vec3 cosine_hemisphere(const Vec3& n, float u1, float u2) {
  // A uniform point on the unit disk projected up to the hemisphere has density cos(theta) / pi.
  const float r = std::sqrt(u1);
  const float phi = 2.0f * std::numbers::pi_v<float> * u2;
  const float z = std::sqrt(std::fmax(0.0f, 1.0f - u1));  // u1 <= 1 - 2^-24, so z >= 2^-12
  Vec3 t, b;
  orthonormal_basis(n, t, b);
  return normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * z);
}

}  // namespace rayaccel
