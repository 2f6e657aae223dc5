// Image: an 8-bit RGB raster (row 0 at the top) with clipped pixel and rectangle writes, saved as PNG through
// stb_image_write.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace rayaccel {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  friend constexpr bool operator==(const Rgb&, const Rgb&) = default;
};

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< width * height * 3, row-major from the top row

  /// A width x height image filled with `fill` (sizes must be > 0, else Error).
  static Image filled(int width, int height, Rgb fill);
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
  /// The pixel at (x, y), which must lie inside the image.
  Rgb at(int x, int y) const {
    const std::uint8_t* p = &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
    return {p[0], p[1], p[2]};
  }
  /// Writes pixel (x, y); does nothing outside the image.
  void set(int x, int y, Rgb c) {
    if (!contains(x, y)) return;
    std::uint8_t* p = &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
  }
  /// Fills the rectangle [x, x + w) x [y, y + h), clipped to the image.
  void fill_rect(int x, int y, int w, int h, Rgb c);
  /// Writes a PNG; throws Error naming the path when it cannot be written (or the image is empty or inconsistent).
  void save_png(const std::filesystem::path& path) const;
};

}  // namespace rayaccel
