// Image fills and PNG output; the one translation unit that compiles stb_image_write.
#include "rayaccel/render/image.h"

#include <algorithm>
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/core/output_file.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wpedantic"
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>
#pragma GCC diagnostic pop

namespace rayaccel {

Image Image::filled(int width, int height, Rgb fill) {
  if (width <= 0 || height <= 0) {
    throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) + " is not positive");
  }
  Image image;
  image.width = width;
  image.height = height;
  image.rgb.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  for (std::size_t i = 0; i < image.rgb.size(); i += 3) {
    image.rgb[i] = fill.r;
    image.rgb[i + 1] = fill.g;
    image.rgb[i + 2] = fill.b;
  }
  return image;
}

void Image::fill_rect(int x, int y, int w, int h, Rgb c) {
  const int x0 = std::max(x, 0), y0 = std::max(y, 0);
  const int x1 = std::min(x + w, width), y1 = std::min(y + h, height);
  for (int py = y0; py < y1; ++py) {
    for (int px = x0; px < x1; ++px) set(px, py, c);
  }
}

void Image::save_png(const std::filesystem::path& path) const {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<std::size_t>(width) * height * 3) {
    throw Error("cannot write PNG '" + path.string() + "': the image is empty or its pixel buffer has the wrong size");
  }
  std::vector<std::byte> png;
  const auto append = [](void* context, void* data, int size) {
    auto* out = static_cast<std::vector<std::byte>*>(context);
    const auto* bytes = static_cast<const std::byte*>(data);
    out->insert(out->end(), bytes, bytes + size);
  };
  if (stbi_write_png_to_func(append, &png, width, height, 3, rgb.data(), width * 3) == 0) {
    throw Error("cannot write PNG '" + path.string() + "': encoding failed");
  }
  write_file_atomically(path, png, "PNG");
}

}  // namespace rayaccel
