// The ray kinds benchmarks and renders trace (primary, cosine diffuse, ambient-occlusion shadow, point-light shadow),
// deterministic per seed; secondary origins offset as pbrt does (3rd ed., 3.9) or by a fixed distance.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/scene/scene.h"
#include "rayaccel/render/camera.h"

namespace rayaccel {

/// width * height rays, row-major from the top-left pixel (both > 0, else Error).
std::vector<Ray> primary_rays(const Camera& camera, int width, int height);

/// The order in which packet traversals get camera rays: indices into primary_rays(camera, width, height) such that
/// each run of eight consecutive entries is a 4 x 2 tile of pixels (its top row left to right, then its bottom row).
/// The tiles cover the first width - width % 4 columns of the first height - height % 2 rows and come in row-major
/// order (left to right, then top to bottom); the pixels no whole tile covers (the right strip of width % 4 columns,
/// then the last row when height is odd) follow in row-major order. Every pixel appears once (both > 0, else Error).
std::vector<std::size_t> packet_tile_order(int width, int height);

/// Where a secondary ray starts. By default offset_ray_origin() (pbrt's conservative offset: the ray cannot hit
/// the surface it leaves); with fixed_distance > 0, the surface point moved that far along the normal, toward the
/// side the ray leaves by, the "epsilon" many renderers use (rays may then start behind nearby geometry or, at
/// grazing angles, re-hit their own surface: what those renderers' rays look like).
struct OriginOffset {
  float fixed_distance = 0.0f;
};

/// One cosine-weighted bounce from each hit of `rays` (misses produce none; output order = order of the hits),
/// on the side the ray came from, unbounded (t in [0, +inf)), unit direction. The random numbers of ray i depend
/// only on (seed, i), never on the thread count. Each origin is placed by `offset` (by default lifted off the
/// surface by offset_ray_origin(), so the ray cannot hit the surface it leaves).
std::vector<Ray> diffuse_rays(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> hits,
                              std::uint64_t seed, OriginOffset offset = {});
/// Like diffuse_rays() but with t_max = max_distance (ambient-occlusion rays, traced with occluded()).
std::vector<Ray> shadow_rays(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> hits,
                             float max_distance, std::uint64_t seed, OriginOffset offset = {});
/// One shadow ray from each hit of `rays` to the point `light` (misses produce none; output order = order of the
/// hits): direction light - origin (not normalized), t in [0, 1), so the light point itself is never a hit, traced
/// with occluded(). Hits whose surface faces away from the light still get a ray (leaving by the far side).
std::vector<Ray> light_rays(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> hits,
                            const Vec3& light, OriginOffset offset = {});

/// A hit point recomputed from the primitive, with a per-axis bound on its distance from the true surface.
struct SurfacePoint {
  Vec3 point;
  Vec3 error;  ///< |point - exact surface point| <= error on each axis
};

/// The surface point of a found hit. Triangles: from the barycentrics, p = (1-u-v) v0 + u v1 + v v2, error
/// gamma(7) * sum |b_i v_i| (pbrt's bound; independent of the ray's length, so distant origins do not widen it).
/// Spheres: o + t d projected back onto the sphere, error gamma(6) * (|center| + |p - center|). User primitives:
/// o + t d with a loose bound of 2^-16 * (|o| + |t d|), since their kernel's accuracy is unknown.
SurfacePoint surface_point(const Scene& scene, const Ray& ray, const Hit& hit);

/// The origin of a ray leaving `surface` with unit normal `n` toward direction `w` (dot(w, n) > 0 expected, n
/// flipped otherwise): moved along n by dot(|n|, error), far enough to clear the error box, then one ulp further
/// along n on each axis where n is nonzero, so neither the rounding of the addition nor an exact (error 0) point
/// leaves it on the surface (pbrt's OffsetRayOrigin, plus the exact case). A ray from there with t_min = 0 and
/// dot(w, n) > 0 does not re-hit the surface it left.
Vec3 offset_ray_origin(const SurfacePoint& surface, const Vec3& n, const Vec3& w);

}  // namespace rayaccel
