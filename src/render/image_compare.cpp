// PNG input (stb_image, compiled here with internal linkage) and image error measures.
#include "rayaccel/render/image_compare.h"

#include <cmath>
#include <limits>
#include <string>

#include "rayaccel/core/error.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wconversion"
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace rayaccel {

Image load_png(const std::filesystem::path& path) {
  int width = 0, height = 0, channels = 0;
  stbi_uc* data = stbi_load(path.string().c_str(), &width, &height, &channels, 3);
  if (data == nullptr) {
    throw Error("cannot read image '" + path.string() + "': " + (stbi_failure_reason() ? stbi_failure_reason() : "?"));
  }
  Image image;
  image.width = width;
  image.height = height;
  image.rgb.assign(data, data + static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  stbi_image_free(data);
  return image;
}

ImageError compare_images(const Image& image, const Image& reference) {
  if (image.width != reference.width || image.height != reference.height) {
    throw Error("cannot compare a " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                " image with a " + std::to_string(reference.width) + "x" + std::to_string(reference.height) +
                " reference");
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < image.rgb.size(); ++i) {
    const double d = static_cast<double>(image.rgb[i]) - static_cast<double>(reference.rgb[i]);
    sum += d * d;
  }
  ImageError e;
  e.rmse = image.rgb.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(image.rgb.size()));
  e.psnr = e.rmse == 0.0 ? std::numeric_limits<double>::infinity() : 20.0 * std::log10(255.0 / e.rmse);
  return e;
}

}  // namespace rayaccel
