// Reading a PNG back and measuring how far one image is from a reference: root-mean-square error over the 8-bit
// channels and the peak signal-to-noise ratio derived from it.
#pragma once

#include <filesystem>

#include "rayaccel/render/image.h"

namespace rayaccel {

/// Reads an 8-bit PNG (any channel count, converted to RGB); throws Error naming the path when it cannot.
Image load_png(const std::filesystem::path& path);

struct ImageError {
  double rmse = 0.0;  ///< sqrt(mean of squared channel differences), in 8-bit units (0..255)
  double psnr = 0.0;  ///< 20 log10(255 / rmse) in dB; +inf for identical images
};

/// The error of `image` against `reference`; throws Error when their sizes differ.
ImageError compare_images(const Image& image, const Image& reference);

}  // namespace rayaccel
