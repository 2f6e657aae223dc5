// The ray kinds benchmarks and renders trace: primary camera rays, one cosine-weighted diffuse bounce per hit, and
// short ambient-occlusion shadow rays. Deterministic for a given seed.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/core/scene.h"
#include "rayaccel/render/camera.h"

namespace rayaccel {

/// width * height rays, row-major from the top-left pixel.
std::vector<Ray> primary_rays(const Camera& camera, int width, int height);
/// One cosine-weighted bounce from each hit of `rays` (misses produce none), on the side the ray came from,
/// unbounded; origins are offset off the surface by a small epsilon in t_min.
std::vector<Ray> diffuse_rays(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> hits,
                              std::uint64_t seed);
/// Like diffuse_rays() but with t_max = max_distance (ambient-occlusion rays, traced with occluded()).
std::vector<Ray> shadow_rays(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> hits,
                             float max_distance, std::uint64_t seed);

}  // namespace rayaccel
