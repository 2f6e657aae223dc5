// Anti-aliasing by sampling shared pixel corners, each point traced once: uniform n x n supersampling, and adaptive
// subdivision (Whitted 1980) where a square's corners differ in contrast (Mitchell 1987) by at least a threshold.
#pragma once

#include <cstdint>
#include <functional>
#include <string_view>
#include <vector>

#include "rayaccel/core/vec3.h"

namespace rayaccel {

struct AntiAliasing {
  enum class Mode { uniform, adaptive };
  Mode mode = Mode::uniform;
  int n = 1;               ///< uniform: sub-squares per pixel side (a power of two, 1 to 64)
  float threshold = 0.1f;  ///< adaptive: subdivide while the corners' contrast >= threshold (0: always)
  int max_level = 2;       ///< adaptive: at most 2^max_level sub-squares per pixel side (0 to 6)
};

/// "uniform" or "uniform:n=N", "adaptive" or "adaptive:threshold=T,max_level=L"; throws Error naming the bad part.
AntiAliasing parse_anti_aliasing(std::string_view text);

/// Sub-squares per pixel side on the finest grid the sampler may use: n, or 2^max_level.
int finest_subdivision(const AntiAliasing& aa);

/// Mitchell's contrast of a set of colours: the largest over the three channels of (max - min) / (max + min),
/// 0 where max + min is 0.
float contrast(const Vec3* colours, int count);

struct SampledImage {
  int width = 0;
  int height = 0;
  std::vector<Vec3> pixels;          ///< linear colour per pixel, row by row
  /// Samples of each pixel: its four corners, plus the other points it traced (a point on an edge it shares with a
  /// neighbour counts for the one that traced it first).
  std::vector<std::uint32_t> samples;
  std::uint64_t sample_count = 0;  ///< samples traced in all, each point once (uniform n: (n w + 1) (n h + 1))
};

/// Calls sample(x, y, key) at image-plane points (x, y) in pixels ((0, 0) the top-left corner of the image, (width,
/// height) the bottom-right) and filters them into pixels: a square's value is the mean of its four corners or, when
/// subdivided, the mean of its four quarters' values. key identifies the point on the finest grid (the same point
/// always gets the same key, whichever pixel or mode asks), for reproducible random numbers. sample may be called
/// from several threads at once. progress (may be empty) gets the fraction done.
SampledImage sample_image(int width, int height, const AntiAliasing& aa,
                          const std::function<Vec3(float x, float y, std::uint64_t key)>& sample,
                          const std::function<void(float)>& progress = {});

}  // namespace rayaccel
