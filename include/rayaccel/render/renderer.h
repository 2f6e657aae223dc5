// Renders a scene through any accelerator: shading by normals or ambient occlusion, or a heat map of traversal
// cost per pixel (nodes visited + primitives tested) with a colour scale and legend, written as PNG.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string_view>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/core/scene.h"
#include "rayaccel/core/stats.h"
#include "rayaccel/render/camera.h"

namespace rayaccel {

enum class ShadingMode { normals, ambient_occlusion, heatmap };
/// Parses "normals", "ao" or "heatmap"; throws Error listing them otherwise.
ShadingMode parse_shading_mode(std::string_view text);

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< width * height * 3, row-major from the top row
  /// Writes a PNG; throws Error naming the path when it cannot be written.
  void save_png(const std::filesystem::path& path) const;
};

struct RenderSettings {
  int width = 512;
  int height = 512;
  ShadingMode mode = ShadingMode::normals;
  int ao_samples = 8;                 ///< shadow rays per hit in ao mode
  float ao_distance_fraction = 0.1f;  ///< ao ray length as a fraction of the scene box diagonal
  std::uint64_t seed = 1;
  /// Called with the fraction done (0..1) as rows finish; may be empty.
  std::function<void(float)> progress;
};

struct RenderResult {
  Image image;
  double trace_milliseconds = 0.0;
  TraversalStats total;   ///< summed over every ray traced
  std::uint64_t rays = 0;
};

RenderResult render(const Accelerator& accel, const Scene& scene, const Camera& camera, const RenderSettings& settings);

}  // namespace rayaccel
