// Directed rounding of double results to float where a float bound must enclose an exact value: round to nearest
// and one ulp step by bit manipulation, as pbrt's NextFloatUp/Down (3rd ed., 3.9), no libm call.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace rayaccel {

/// gamma(n) = n u / (1 - n u), u = 2^-24: the relative rounding bound of n float operations (pbrt, section 3.9.1).
constexpr float float_gamma(int n) { return float(n) * 0x1p-24f / (1.0f - float(n) * 0x1p-24f); }

/// The next float above f (+inf and NaN stay; -0 and +0 step to the smallest subnormal).
inline float next_float_up(float f) {
  if (std::isnan(f) || f == std::numeric_limits<float>::infinity()) return f;
  if (f == 0.0f) return std::numeric_limits<float>::denorm_min();
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(f);
  return std::bit_cast<float>(f > 0.0f ? bits + 1 : bits - 1);
}

/// The next float below f (-inf and NaN stay; -0 and +0 step to the negative smallest subnormal).
inline float next_float_down(float f) {
  if (std::isnan(f) || f == -std::numeric_limits<float>::infinity()) return f;
  if (f == 0.0f) return -std::numeric_limits<float>::denorm_min();
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(f);
  return std::bit_cast<float>(f > 0.0f ? bits - 1 : bits + 1);
}

/// The largest float <= x (x finite or infinite; NaN stays NaN).
inline float round_down_to_float(double x) {
  const float f = static_cast<float>(x);
  return double(f) > x ? next_float_down(f) : f;
}

/// The smallest float >= x (x finite or infinite; NaN stays NaN).
inline float round_up_to_float(double x) {
  const float f = static_cast<float>(x);
  return double(f) < x ? next_float_up(f) : f;
}

}  // namespace rayaccel
