// Primary, diffuse and shadow ray workloads; robust secondary-ray origins after pbrt (3rd ed., section 3.9).
#include "rayaccel/render/workloads.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/core/float_rounding.h"
#include "rayaccel/render/sampling.h"
#include "rayaccel/render/shading.h"

namespace rayaccel {

namespace {

/// Unit normal at the hit facing the side the ray came from; a missing normal falls back to -direction.
Vec3 facing_normal(const Scene& scene, const Ray& ray, const Hit& hit) {
  Vec3 n = geometric_normal(scene, ray, hit);
  if (!is_finite(n) || n == Vec3{}) n = -normalize(ray.direction);
  return dot(n, ray.direction) > 0.0f ? -n : n;
}

/// Where a ray leaving `surface` toward `w` starts (see OriginOffset); n faces the incoming ray.
Vec3 secondary_origin(const SurfacePoint& surface, const Vec3& n, const Vec3& w, OriginOffset offset) {
  if (offset.fixed_distance > 0.0f) return surface.point + (dot(w, n) < 0.0f ? -n : n) * offset.fixed_distance;
  return offset_ray_origin(surface, n, w);
}

void check_offset(const OriginOffset& offset) {
  if (!(offset.fixed_distance >= 0.0f && std::isfinite(offset.fixed_distance))) {
    throw Error("secondary rays: fixed origin offset " + std::to_string(offset.fixed_distance) +
                " is not a finite distance >= 0");
  }
}

/// Calls make(i, slot) for each hit i, in parallel; slot = its place among the hits, so the output order is the
/// input order whatever the thread count. Returns the number of hits.
template <class Make>
std::size_t for_each_hit(std::span<const Ray> rays, std::span<const Hit> hits, std::vector<Ray>& out,
                         const Make& make) {
  if (rays.size() != hits.size()) {
    throw Error("secondary rays: " + std::to_string(rays.size()) + " rays but " + std::to_string(hits.size()) +
                " hits");
  }
  std::vector<std::size_t> slot(hits.size());
  std::size_t count = 0;
  for (std::size_t i = 0; i < hits.size(); ++i) {
    slot[i] = count;
    count += hits[i].found() ? 1 : 0;
  }
  out.assign(count, Ray{});
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, hits.size(), 256), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      if (hits[i].found()) make(i, out[slot[i]]);
    }
  });
  return count;
}

/// One bounce ray per hit, t in [0, max_distance]; the shared body of diffuse_rays() and shadow_rays().
std::vector<Ray> bounce_rays(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> hits,
                             float max_distance, std::uint64_t seed, OriginOffset offset) {
  check_offset(offset);
  std::vector<Ray> out;
  for_each_hit(rays, hits, out, [&](std::size_t i, Ray& r) {
    const Vec3 n = facing_normal(scene, rays[i], hits[i]);
    const Vec3 w = cosine_hemisphere(n, uniform_float(seed, i, 0), uniform_float(seed, i, 1));
    r.origin = secondary_origin(surface_point(scene, rays[i], hits[i]), n, w, offset);
    r.direction = w;
    r.t_min = 0.0f;
    r.t_max = max_distance;
  });
  return out;
}

}  // namespace

std::vector<Ray> primary_rays(const Camera& camera, int width, int height) {
  const CameraFrame frame = camera.frame(width, height);
  std::vector<Ray> rays(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) {
      for (int x = 0; x < width; ++x) rays[static_cast<std::size_t>(y) * width + x] = frame.ray(x, y);
    }
  });
  return rays;
}

std::vector<std::size_t> packet_tile_order(int width, int height) {
  if (width <= 0 || height <= 0) {
    throw Error("packet tiles: bad image size " + std::to_string(width) + "x" + std::to_string(height));
  }
  constexpr int kTileWidth = 4, kTileHeight = 2;
  const auto pixel = [width](int x, int y) { return static_cast<std::size_t>(y) * width + x; };
  const int tiled_width = width - width % kTileWidth;
  const int tiled_height = height - height % kTileHeight;
  std::vector<std::size_t> order;
  order.reserve(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  for (int ty = 0; ty < tiled_height; ty += kTileHeight) {
    for (int tx = 0; tx < tiled_width; tx += kTileWidth) {
      for (int y = ty; y < ty + kTileHeight; ++y) {
        for (int x = tx; x < tx + kTileWidth; ++x) order.push_back(pixel(x, y));
      }
    }
  }
  for (int y = 0; y < height; ++y) {
    for (int x = y < tiled_height ? tiled_width : 0; x < width; ++x) order.push_back(pixel(x, y));
  }
  return order;
}

std::vector<Ray> diffuse_rays(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> hits,
                              std::uint64_t seed, OriginOffset offset) {
  return bounce_rays(scene, rays, hits, std::numeric_limits<float>::infinity(), seed, offset);
}

std::vector<Ray> shadow_rays(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> hits,
                             float max_distance, std::uint64_t seed, OriginOffset offset) {
  if (!(max_distance >= 0.0f)) throw Error("shadow rays: max_distance " + std::to_string(max_distance) + " < 0");
  return bounce_rays(scene, rays, hits, max_distance, seed, offset);
}

std::vector<Ray> light_rays(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> hits,
                            const Vec3& light, OriginOffset offset) {
  check_offset(offset);
  if (!is_finite(light)) throw Error("light rays: the light position is not finite");
  std::vector<Ray> out;
  for_each_hit(rays, hits, out, [&](std::size_t i, Ray& r) {
    const Vec3 n = facing_normal(scene, rays[i], hits[i]);
    const SurfacePoint surface = surface_point(scene, rays[i], hits[i]);
    r.origin = secondary_origin(surface, n, light - surface.point, offset);
    r.direction = light - r.origin;
    r.t_min = 0.0f;
    r.t_max = 0x1.fffffep-1f;  // the largest float below 1: the light point itself is not a hit
  });
  return out;
}

SurfacePoint surface_point(const Scene& scene, const Ray& ray, const Hit& hit) {
  switch (scene.kind()) {
    case PrimitiveKind::triangles: {
      const auto& v = scene.triangle(hit.prim_id);
      const float b0 = 1.0f - hit.u - hit.v;
      const Vec3 p0 = v[0] * b0, p1 = v[1] * hit.u, p2 = v[2] * hit.v;
      return {p0 + p1 + p2, (abs(p0) + abs(p1) + abs(p2)) * float_gamma(7)};
    }
    case PrimitiveKind::spheres: {
      const Sphere& s = scene.spheres()[hit.prim_id];
      const Vec3 raw = ray.origin + ray.direction * hit.t;
      const Vec3 radial = normalize(raw - s.center) * s.radius;
      return {s.center + radial, (abs(s.center) + abs(radial)) * float_gamma(6)};
    }
    case PrimitiveKind::user:
      break;
  }
  const Vec3 travel = ray.direction * hit.t;
  return {ray.origin + travel, (abs(ray.origin) + abs(travel)) * 0x1p-16f};
}

Vec3 offset_ray_origin(const SurfacePoint& surface, const Vec3& n, const Vec3& w) {
  const Vec3 side = dot(w, n) < 0.0f ? -n : n;
  Vec3 origin = surface.point + side * dot(abs(n), surface.error);
  // One more ulp along the normal per axis: the addition may have rounded back toward the surface, and a point
  // computed exactly (error 0) still leaves the surface.
  for (int axis = 0; axis < 3; ++axis) {
    if (side[axis] > 0.0f) origin[axis] = std::nextafter(origin[axis], std::numeric_limits<float>::infinity());
    if (side[axis] < 0.0f) origin[axis] = std::nextafter(origin[axis], -std::numeric_limits<float>::infinity());
  }
  return origin;
}

}  // namespace rayaccel
