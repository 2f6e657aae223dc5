// Directed rounding of double results to float, used where a float bound must enclose an exact value (fitted
// bounding volumes, the k-DOP ray projections). Round-to-nearest followed by a one-ulp correction, as in pbrt's
// NextFloatUp/NextFloatDown (Pharr, Jakob, Humphreys, "Physically Based Rendering", 3rd ed., section 3.9).
#pragma once

#include <cmath>
#include <limits>

namespace rayaccel {

/// The largest float <= x (x finite or infinite; NaN stays NaN).
inline float round_down_to_float(double x) {
  float f = static_cast<float>(x);
  if (double(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

/// The smallest float >= x (x finite or infinite; NaN stays NaN).
inline float round_up_to_float(double x) {
  float f = static_cast<float>(x);
  if (double(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

}  // namespace rayaccel
