// The bench's ray sets: primary rays, then diffuse bounces, shadow, occlusion and light rays from their hits, and the
// primary and light rays in 4 x 2 pixel tiles for the packet kinds, the primary rays again for beams (lengths and
// offsets below).
#include <algorithm>
#include <cmath>

#include "bench.h"
#include "cli_common.h"
#include "rayaccel/render/workloads.h"

namespace rayaccel::cli {

namespace {

constexpr float kShadowDistanceFraction = 0.1f;     // shadow ray length / scene box diagonal
constexpr float kOcclusionDistanceFraction = 0.25f; // occlusion ray length / scene box diagonal
constexpr float kFixedOffsetFraction = 1e-4f;       // occlusion rays' origin offset / scene box diagonal
constexpr float kLightHeightFraction = 0.45f;       // light above the box center along the camera's up / extent
constexpr std::uint64_t kDiffuseSeed = 1;
constexpr std::uint64_t kShadowSeed = 2;
constexpr std::uint64_t kOcclusionSeed = 3;

/// The point light of the light rays: above the center of the scene's box along the camera's up direction, inside
/// the box (near the ceiling of a room, above an object).
Vec3 light_position(const Scene& scene, const Camera& camera) {
  if (scene.bounds().is_empty()) return {};
  const Vec3 up = normalize(camera.up);
  const Vec3 extent = scene.bounds().extent();
  const float height = std::abs(up.x) * extent.x + std::abs(up.y) * extent.y + std::abs(up.z) * extent.z;
  return scene.bounds().center() + up * (kLightHeightFraction * height);
}

/// The per-pixel values of an N x N image (row by row) reordered into packet_tile_order(), as the packet kinds take
/// their rays.
template <class T>
std::vector<T> in_tile_order(const std::vector<T>& per_pixel, int resolution) {
  std::vector<T> tiled;
  tiled.reserve(per_pixel.size());
  for (const std::size_t i : packet_tile_order(resolution, resolution)) tiled.push_back(per_pixel[i]);
  return tiled;
}

/// The primitive each secondary ray starts on: the secondary generators make one ray per hit, in the hits' order.
std::vector<std::uint32_t> origin_primitives(const std::vector<Hit>& hits) {
  std::vector<std::uint32_t> prims;
  for (const Hit& h : hits) {
    if (h.found()) prims.push_back(h.prim_id);
  }
  return prims;
}

}  // namespace

std::vector<RayKind> parse_kinds(const std::string& text) {
  constexpr RayKind kAll[] = {RayKind::primary,      RayKind::diffuse,     RayKind::shadow,
                              RayKind::occlusion,    RayKind::light,       RayKind::packet,
                              RayKind::light_packet, RayKind::diffuse_skip, RayKind::shadow_skip,
                              RayKind::occlusion_skip, RayKind::light_skip, RayKind::beam};
  std::vector<RayKind> kinds;
  for (const auto& item : split_list(text)) {
    const auto known = std::find_if(std::begin(kAll), std::end(kAll), [&](RayKind k) { return item == to_string(k); });
    if (known == std::end(kAll)) {
      throw UsageError("--rays: unknown ray kind '" + item +
                       "' (known: primary, diffuse, shadow, occlusion, light, packet, light_packet, diffuse_skip, "
                       "shadow_skip, occlusion_skip, light_skip, beam)");
    }
    if (std::find(kinds.begin(), kinds.end(), *known) == kinds.end()) kinds.push_back(*known);
  }
  if (kinds.empty()) throw UsageError("--rays: '" + text + "' names no ray kind");
  return kinds;
}

std::vector<Workload> make_workloads(const Scene& scene, const Camera& camera, const std::vector<RayKind>& kinds,
                                     int resolution, const std::vector<Ray>& primary,
                                     const std::vector<Hit>& primary_hits) {
  std::vector<Workload> workloads;
  const float diagonal = scene.bounds().is_empty() ? 1.0f : length(scene.bounds().extent());
  for (const RayKind kind : kinds) {
    Workload w;
    w.kind = kind;
    if (w.skips()) w.skip = origin_primitives(primary_hits);
    switch (kind) {
      case RayKind::primary: w.rays = primary; break;
      case RayKind::diffuse:
      case RayKind::diffuse_skip: w.rays = diffuse_rays(scene, primary, primary_hits, kDiffuseSeed); break;
      case RayKind::shadow:
      case RayKind::shadow_skip:
        w.rays = shadow_rays(scene, primary, primary_hits, kShadowDistanceFraction * diagonal, kShadowSeed);
        break;
      case RayKind::occlusion:
      case RayKind::occlusion_skip:
        w.rays = shadow_rays(scene, primary, primary_hits, kOcclusionDistanceFraction * diagonal, kOcclusionSeed,
                             OriginOffset{kFixedOffsetFraction * diagonal});
        break;
      case RayKind::light:
      case RayKind::light_skip:
        w.rays = light_rays(scene, primary, primary_hits, light_position(scene, camera));
        break;
      case RayKind::packet: w.rays = in_tile_order(primary, resolution); break;
      case RayKind::beam:
        w.rays = primary;
        w.scene = &scene;
        w.frame = camera.frame(resolution, resolution);
        break;
      case RayKind::light_packet:
        // The light rays of the primary hits taken in tile order: the same rays as `light`, neighbours together.
        w.rays = light_rays(scene, in_tile_order(primary, resolution), in_tile_order(primary_hits, resolution),
                            light_position(scene, camera));
        break;
    }
    workloads.push_back(std::move(w));
  }
  return workloads;
}

}  // namespace rayaccel::cli
