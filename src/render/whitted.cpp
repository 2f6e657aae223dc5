// The recursive ray tracer: Whitted 1980 shading, Hall & Greenberg 1983 adaptive tree depth, any-hit shadow rays.
#include "rayaccel/render/whitted.h"

#include <tbb/combinable.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/render/colormap.h"
#include "rayaccel/render/heatmap.h"
#include "rayaccel/render/sampling.h"
#include "rayaccel/render/shading.h"
#include "rayaccel/render/workloads.h"

namespace rayaccel {

namespace {

constexpr float kBelowOne = 0x1.fffffep-1f;  // shadow rays end just before the light sample
constexpr std::uint64_t kStreamSeed = 0x5eedf00dULL;

/// The random stream of a child ray: a pure function of the parent's stream and which child it is.
std::uint64_t child_stream(std::uint64_t stream, std::uint32_t child) { return hash_counter(stream, child, 17); }

Vec3 mix(const Vec3& a, const Vec3& b, float t) { return a * (1.0f - t) + b * t; }

void add_stats(RayCounts& counts, const TraversalStats& stats) {
  counts.nodes_visited += stats.nodes_visited;
  counts.primitives_tested += stats.primitives_tested;
}

}  // namespace

// Member by member, as BeamStats' (generalized/beam_tracer.cpp): other counters, nothing to share.
RayCounts& RayCounts::operator+=(const RayCounts& o) {
  camera += o.camera;
  shadow += o.shadow;
  reflection += o.reflection;
  refraction += o.refraction;
  nodes_visited += o.nodes_visited;
  primitives_tested += o.primitives_tested;
  return *this;
}

void check_settings(const WhittedSettings& s) {
  if (s.max_depth < 0 || s.max_depth > 64) throw Error("max depth " + std::to_string(s.max_depth) + " is not in [0, 64]");
  if (!(s.min_weight >= 0.0f && s.min_weight <= 1.0f)) {
    throw Error("min weight " + std::to_string(s.min_weight) + " is not in [0, 1]");
  }
  if (!(s.ambient >= 0.0f && std::isfinite(s.ambient))) throw Error("ambient " + std::to_string(s.ambient) + " < 0");
  if (!is_finite(s.up) || s.up == Vec3{}) throw Error("the up direction must be finite and nonzero");
}

WhittedTracer::WhittedTracer(const Accelerator& accel, const Scene& scene, const SceneMaterials& materials,
                             const std::vector<Light>& lights, const WhittedSettings& settings)
    : accel_(accel), scene_(scene), materials_(materials), lights_(lights), settings_(settings) {
  check_settings(settings);
  if (!materials.prim_material.empty() && materials.prim_material.size() != scene.primitive_count()) {
    throw Error("materials: " + std::to_string(materials.prim_material.size()) + " entries for " +
                std::to_string(scene.primitive_count()) + " primitives");
  }
  for (const std::uint32_t m : materials.prim_material) {
    if (m >= materials.table.size()) throw Error("materials: index " + std::to_string(m) + " outside the table");
  }
  for (const Material& m : materials.table) check_material(m);
  for (const Light& l : lights) {
    if (!is_finite(l.position) || !is_finite(l.intensity) || !(l.radius >= 0.0f) || l.samples < 1) {
      throw Error("lights: a light needs a finite position and intensity, radius >= 0 and samples >= 1");
    }
  }
}

Vec3 WhittedTracer::radiance(const Ray& ray, std::uint64_t stream, RayCounts& counts) const {
  ++counts.camera;
  return trace(ray, 0, 1.0f, stream, counts);
}

Vec3 WhittedTracer::background(const Vec3& direction) const {
  const float t = 0.5f + 0.5f * dot(normalize(direction), normalize(settings_.up));
  return mix(Vec3{0.05f, 0.05f, 0.06f}, Vec3{0.45f, 0.55f, 0.75f}, std::clamp(t, 0.0f, 1.0f));
}

bool WhittedTracer::shadowed(const Ray& ray, RayCounts& counts) const {
  ++counts.shadow;
  TraversalStats stats;
  const bool blocked = settings_.any_hit_shadows ? accel_.occluded(ray, stats) : accel_.intersect(ray, stats).found();
  add_stats(counts, stats);
  return blocked;
}

Vec3 WhittedTracer::direct_light(const Vec3& normal, const Vec3& albedo, const SurfacePoint& surface,
                                 std::uint64_t stream, RayCounts& counts) const {
  Vec3 total{};
  for (std::size_t l = 0; l < lights_.size(); ++l) {
    const Light& light = lights_[l];
    const int samples = light.radius > 0.0f ? light.samples : 1;
    const std::uint64_t light_stream = hash_counter(stream, l, 23);
    Vec3 sum{};
    for (int k = 0; k < samples; ++k) {
      const Vec3 target = light_sample(light, light_stream, k);
      const Vec3 to_light = target - surface.point;
      const float distance2 = dot(to_light, to_light);
      const float cosine = distance2 > 0.0f ? dot(normal, to_light) / std::sqrt(distance2) : 0.0f;
      if (!(cosine > 0.0f)) continue;  // the light is behind the surface: no shadow ray needed
      Ray shadow;
      shadow.origin = offset_ray_origin(surface, normal, to_light);
      shadow.direction = target - shadow.origin;
      shadow.t_min = 0.0f;
      shadow.t_max = kBelowOne;
      if (shadowed(shadow, counts)) continue;
      sum += light.intensity * (cosine / distance2);
    }
    total += sum * (1.0f / static_cast<float>(samples));
  }
  return albedo * total;
}

Vec3 WhittedTracer::trace(const Ray& ray, int depth, float weight, std::uint64_t stream, RayCounts& counts) const {
  TraversalStats stats;
  const Hit hit = accel_.intersect(ray, stats);
  add_stats(counts, stats);
  if (!hit.found()) return background(ray.direction);

  const Material& m = materials_.of(hit.prim_id);
  const Vec3 d = normalize(ray.direction);
  const Vec3 n = geometric_normal(scene_, ray, hit);   // as the primitive is oriented
  const Vec3 facing = dot(n, d) > 0.0f ? -n : n;        // toward the side the ray came from
  const SurfacePoint surface = surface_point(scene_, ray, hit);
  Vec3 colour{};
  const float diffuse = 1.0f - m.mirror - m.transmission;
  if (diffuse > 0.0f) {
    const Vec3 albedo = m.diffuse * diffuse;
    colour += albedo * settings_.ambient + direct_light(facing, albedo, surface, stream, counts);
  }

  // Weights of the mirror direction and of the refracted direction (Fresnel equations for unpolarized light).
  float reflected = m.mirror, refracted = 0.0f;
  Vec3 refraction_direction;
  if (m.transmission > 0.0f) {
    const bool entering = dot(d, n) < 0.0f;
    const float eta = entering ? 1.0f / m.ior : m.ior;  // n_incident / n_transmitted
    const float cos_i = std::min(1.0f, -dot(d, facing));
    const float sin2_t = eta * eta * std::max(0.0f, 1.0f - cos_i * cos_i);
    if (sin2_t >= 1.0f) {
      reflected += m.transmission;  // total internal reflection
    } else {
      const float cos_t = std::sqrt(1.0f - sin2_t);
      const float rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
      const float rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
      const float fresnel = 0.5f * (rs * rs + rp * rp);
      reflected += m.transmission * fresnel;
      refracted = m.transmission * (1.0f - fresnel);
      refraction_direction = normalize(d * eta + facing * (eta * cos_i - cos_t));
    }
  }
  if (depth >= settings_.max_depth) return colour;
  const auto secondary = [&](const Vec3& direction, float part, std::uint32_t child, std::uint64_t& kind_count) {
    // Hall & Greenberg: a ray whose contribution to the pixel would fall below min_weight is not traced.
    if (!(part > 0.0f) || weight * part < settings_.min_weight) return;
    Ray next;
    next.origin = offset_ray_origin(surface, facing, direction);
    next.direction = direction;
    ++kind_count;
    colour += trace(next, depth + 1, weight * part, child_stream(stream, child), counts) * part;
  };
  secondary(d - facing * (2.0f * dot(d, facing)), reflected, 1, counts.reflection);
  if (refracted > 0.0f) secondary(refraction_direction, refracted, 2, counts.refraction);
  return colour;
}

WhittedResult render_whitted(const Accelerator& accel, const Scene& scene, const Camera& camera, int width,
                             int height, const SceneMaterials& materials, const std::vector<Light>& lights,
                             const WhittedSettings& settings, const AntiAliasing& aa,
                             const std::function<void(float)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  const WhittedTracer tracer(accel, scene, materials, lights, settings);
  const CameraFrame frame = camera.frame(width, height);
  tbb::combinable<RayCounts> counts;
  WhittedResult result;
  result.samples = sample_image(
      width, height, aa,
      [&](float x, float y, std::uint64_t key) {
        return tracer.radiance(frame.ray_at(x, y), hash_counter(kStreamSeed, key, 0), counts.local());
      },
      progress);
  counts.combine_each([&](const RayCounts& c) { result.counts += c; });
  result.image = Image::filled(width, height, Rgb{0, 0, 0});
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const Vec3 c = result.samples.pixels[static_cast<std::size_t>(y) * width + x];
      result.image.set(x, y, {encode_srgb(c.x), encode_srgb(c.y), encode_srgb(c.z)});
    }
  }
  result.milliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return result;
}

Image samples_per_pixel_image(const SampledImage& samples) {
  HeatFrame frame;
  frame.width = samples.width;
  frame.height = samples.height;
  frame.cost.assign(samples.samples.begin(), samples.samples.end());
  frame.brightness.assign(frame.cost.size(), 1.0f);
  frame.range = cost_range(frame.cost);
  const CostRange scale{frame.range.min, frame.range.highest, frame.range.highest};
  return draw_heat_frame(frame, scale, HeatCaption{"SAMPLES PER PIXEL", "SAMPLES"});
}

}  // namespace rayaccel
