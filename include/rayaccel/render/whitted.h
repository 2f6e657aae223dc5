// The recursive ray tracer (Whitted 1980): diffuse, mirror and Fresnel-weighted dielectric shading with shadow
// rays, adaptive tree-depth control (Hall & Greenberg 1983) and any-hit shadow rays.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/scene/scene.h"
#include "rayaccel/render/camera.h"
#include "rayaccel/render/image.h"
#include "rayaccel/render/image_sampler.h"
#include "rayaccel/render/lights.h"
#include "rayaccel/render/materials.h"
#include "rayaccel/render/workloads.h"

namespace rayaccel {

/// Rays traced by kind and the traversal work they cost (plain counters, as SplitTreeCounts and BeamStats hold theirs).
struct RayCounts {
  std::uint64_t camera = 0;
  std::uint64_t shadow = 0;
  std::uint64_t reflection = 0;
  std::uint64_t refraction = 0;
  std::uint64_t nodes_visited = 0;
  std::uint64_t primitives_tested = 0;

  std::uint64_t total() const { return camera + shadow + reflection + refraction; }
  RayCounts& operator+=(const RayCounts& o);
};

struct WhittedSettings {
  int max_depth = 5;              ///< secondary rays per path at most (0: camera and shadow rays only)
  float min_weight = 0.0f;        ///< a secondary ray whose weight in the pixel is below this is not traced
  bool any_hit_shadows = true;    ///< shadow rays with occluded() (stop at the first occluder) or intersect()
  float ambient = 0.05f;          ///< constant ambient light on diffuse surfaces
  Vec3 up{0.0f, 1.0f, 0.0f};      ///< the sky's up direction (background gradient)
};

/// Throws Error naming the setting when max_depth is outside [0, 64], min_weight outside [0, 1] or ambient negative.
void check_settings(const WhittedSettings& settings);

/// Traces one camera ray's tree of rays. Stateless apart from its references: one tracer serves many threads.
class WhittedTracer {
 public:
  WhittedTracer(const Accelerator& accel, const Scene& scene, const SceneMaterials& materials,
                const std::vector<Light>& lights, const WhittedSettings& settings);
  /// Linear RGB radiance along `ray` (a camera ray); `stream` seeds the light sampling of the whole tree, and every
  /// ray traced is added to `counts`.
  Vec3 radiance(const Ray& ray, std::uint64_t stream, RayCounts& counts) const;

 private:
  Vec3 trace(const Ray& ray, int depth, float weight, std::uint64_t stream, RayCounts& counts) const;
  Vec3 direct_light(const Vec3& normal, const Vec3& albedo, const SurfacePoint& surface, std::uint64_t stream,
                    RayCounts& counts) const;
  bool shadowed(const Ray& ray, RayCounts& counts) const;
  Vec3 background(const Vec3& direction) const;

  const Accelerator& accel_;
  const Scene& scene_;
  const SceneMaterials& materials_;
  const std::vector<Light>& lights_;
  WhittedSettings settings_;
};

struct WhittedResult {
  Image image;                    ///< sRGB-encoded
  SampledImage samples;           ///< linear pixels and samples per pixel
  RayCounts counts;
  double milliseconds = 0.0;      ///< wall time of the whole render
};

/// Renders width x height pixels of `scene` (which `accel` was built over) seen by `camera`.
WhittedResult render_whitted(const Accelerator& accel, const Scene& scene, const Camera& camera, int width,
                             int height, const SceneMaterials& materials, const std::vector<Light>& lights,
                             const WhittedSettings& settings, const AntiAliasing& aa,
                             const std::function<void(float)>& progress = {});

/// A heat map of samples per pixel (heat_colour() from the fewest to the most), with the heat-map legend.
Image samples_per_pixel_image(const SampledImage& samples);

}  // namespace rayaccel
