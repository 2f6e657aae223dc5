// The heat-map ramp, built in OKLab (Ottosson 2020, "A perceptual color space for image processing") and
// converted to 8-bit sRGB once into a table.
#include "rayaccel/render/colormap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace rayaccel {

namespace {

constexpr int kTableSize = 1024;

struct LinearRgb {
  double r, g, b;
  bool in_gamut() const { return r >= 0.0 && r <= 1.0 && g >= 0.0 && g <= 1.0 && b >= 0.0 && b <= 1.0; }
};

/// OKLab (L, a, b) to linear sRGB, with the matrices of Ottosson's definition.
LinearRgb oklab_to_linear_srgb(double lightness, double a, double b) {
  const double l_ = lightness + 0.3963377774 * a + 0.2158037573 * b;
  const double m_ = lightness - 0.1055613458 * a - 0.0638541728 * b;
  const double s_ = lightness - 0.0894841775 * a - 1.2914855480 * b;
  const double l = l_ * l_ * l_, m = m_ * m_ * m_, s = s_ * s_ * s_;
  return {4.0767416621 * l - 3.3077115913 * m + 0.2309699292 * s,
          -1.2684380046 * l + 2.6097574011 * m - 0.3413193965 * s,
          -0.0041960863 * l - 0.7034186147 * m + 1.7076147010 * s};
}

Rgb ramp(double t) {
  const double lightness = 0.13 + 0.83 * t;
  const double hue = (295.0 + 170.0 * t) * std::numbers::pi / 180.0;
  double chroma = 0.04 + 0.16 * std::sin(std::numbers::pi * (0.1 + 0.8 * t));
  // Gamut mapping: keep lightness and hue, shrink chroma until the colour is displayable.
  LinearRgb c = oklab_to_linear_srgb(lightness, chroma * std::cos(hue), chroma * std::sin(hue));
  while (!c.in_gamut() && chroma > 1e-4) {
    chroma *= 0.97;
    c = oklab_to_linear_srgb(lightness, chroma * std::cos(hue), chroma * std::sin(hue));
  }
  return {encode_srgb(c.r), encode_srgb(c.g), encode_srgb(c.b)};
}

const std::array<Rgb, kTableSize>& ramp_table() {
  static const std::array<Rgb, kTableSize> table = [] {
    std::array<Rgb, kTableSize> entries;
    for (int i = 0; i < kTableSize; ++i) entries[i] = ramp(static_cast<double>(i) / (kTableSize - 1));
    return entries;
  }();
  return table;
}

}  // namespace

std::uint8_t encode_srgb(double linear) {
  const double c = std::isnan(linear) ? 0.0 : std::clamp(linear, 0.0, 1.0);
  const double encoded = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
  return static_cast<std::uint8_t>(std::lround(encoded * 255.0));
}

Rgb heat_colour(float t) {
  const float clamped = std::isnan(t) ? 0.0f : std::clamp(t, 0.0f, 1.0f);
  return ramp_table()[static_cast<int>(std::lround(clamped * (kTableSize - 1)))];
}

}  // namespace rayaccel
