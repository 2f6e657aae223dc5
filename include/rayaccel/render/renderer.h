// Renders a scene through any accelerator: shading by normals or ambient occlusion, or a heat map of traversal
// cost per pixel (nodes visited + primitives tested) with a colour scale and legend, written as PNG.
// Ambient occlusion after Zhukov, Iones, Kronin 1998 (the fraction of short hemisphere rays left unoccluded).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/scene/scene.h"
#include "rayaccel/core/stats.h"
#include "rayaccel/generalized/beam_tracer.h"
#include "rayaccel/render/camera.h"
#include "rayaccel/render/heatmap.h"
#include "rayaccel/render/image.h"

namespace rayaccel {

enum class ShadingMode { normals, ambient_occlusion, heatmap };
/// Parses "normals", "ao" or "heatmap"; throws Error listing them otherwise.
ShadingMode parse_shading_mode(std::string_view text);

struct RenderSettings {
  int width = 512;
  int height = 512;
  ShadingMode mode = ShadingMode::normals;
  int ao_samples = 8;                 ///< shadow rays per hit in ao mode (the first round when adaptive)
  int ao_max_samples = 0;             ///< > ao_samples: adaptive AO, more rounds where the estimate is uncertain
  float ao_error = 0.05f;             ///< adaptive AO: stop once the estimate's standard error is at most this
  float ao_distance_fraction = 0.1f;  ///< ao ray length as a fraction of the scene box diagonal
  std::uint64_t seed = 1;
  /// heatmap mode: the colour scale (min and max; highest is ignored); empty = this image's own cost_range().
  std::optional<CostRange> heat_scale;
  /// Primary visibility by beams (generalized/beam_tracer.h) instead of one ray per pixel: the same hits, so the same
  /// image; normals and ao modes over bvh, bvh_wide and kdtree only (else Error).
  std::optional<generalized::BeamOptions> beams;
  /// Called with the fraction done (0..1) as rows finish; may be empty.
  std::function<void(float)> progress;
};

struct RenderResult {
  Image image;
  double trace_milliseconds = 0.0;  ///< wall time inside the accelerator's batch calls (statistics on)
  TraversalStats total;              ///< summed over every ray traced
  std::uint64_t rays = 0;            ///< primary rays plus ambient-occlusion rays
  HeatFrame heat;                    ///< heatmap mode: what the image was drawn from (to redraw on another scale)
  std::optional<generalized::BeamStats> beam_stats;  ///< with settings.beams: how the primary rays were resolved
};

/// Renders `scene` (which `accel` must have been built over) through accel's batch API, in chunks of rows whose
/// rays are traced in parallel; the progress callback runs on the calling thread after each chunk.
/// - normals: |n| per axis as (r, g, b) at hits (n the geometric normal), a dark blue-grey background at misses.
/// - ambient_occlusion: grey = sRGB-encoded fraction of ao_samples cosine-weighted shadow rays (length
///   ao_distance_fraction times the scene box diagonal) left unoccluded; the same background. With ao_max_samples
///   above ao_samples, a hit whose estimate p has a standard error sqrt(p (1 - p) / n) above ao_error gets another
///   ao_samples rays, round after round, up to ao_max_samples (adaptive sampling: hits whose rays all agree stop).
/// - heatmap: heat_colour() of each primary ray's cost on the linear scale of cost_range() (cheapest ray to the
///   99th percentile) or on settings.heat_scale, with the legend of heatmap.h in the bottom rows. Hit pixels are darkened by 10 to 40 percent
///   with the angle between ray and surface, so shapes stay readable where cost is uniform (brute force);
///   misses and the legend show the plain ramp.
/// The result is the same for any thread count. Throws Error for a non-positive size, or ao_samples < 1 or a
/// negative or non-finite ao_distance_fraction, ao_max_samples in (0, ao_samples), or ao_error outside [0, 0.5] in
/// ambient_occlusion mode.
RenderResult render(const Accelerator& accel, const Scene& scene, const Camera& camera, const RenderSettings& settings);

}  // namespace rayaccel
