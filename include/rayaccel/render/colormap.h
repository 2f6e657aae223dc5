// The heat-map colour ramp: a path through the OKLab perceptual colour space (Ottosson 2020) from near-black
// purple through red and orange to pale yellow (the shape of matplotlib's inferno), with lightness linear in t.
#pragma once

#include <cstdint>

#include "rayaccel/render/image.h"

namespace rayaccel {

/// The ramp at t in [0, 1] (clamped; NaN maps to 0). OKLab lightness rises linearly from 0.13 to 0.96, so equal
/// steps in t read as equal steps in brightness; hue turns from purple (295 deg) to yellow (105 deg); chroma is
/// reduced where needed to stay inside the sRGB gamut. Tabulated once (1024 entries), then a lookup.
Rgb heat_colour(float t);

/// Linear intensity in [0, 1] (clamped; NaN gives 0) to an 8-bit sRGB value with the sRGB transfer curve.
std::uint8_t encode_srgb(double linear);

}  // namespace rayaccel
