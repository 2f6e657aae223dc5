// Soft shadows and anti-aliasing by cones, and their many-ray estimates.
#include "rayaccel/render/cone_effects.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "rayaccel/core/error.h"
#include "rayaccel/generalized/generalized_rays.h"
#include "rayaccel/render/colormap.h"
#include "rayaccel/render/lights.h"
#include "rayaccel/render/shading.h"

namespace rayaccel {

namespace {

using generalized::Cone;

void check(const ConeEffectSettings& s) {
  if (s.width <= 0 || s.height <= 0) {
    throw Error("cones: image size " + std::to_string(s.width) + "x" + std::to_string(s.height) + " is not positive");
  }
  if (s.cone_samples < 1) throw Error("cones: cone_samples " + std::to_string(s.cone_samples) + " < 1");
  if (s.rays < 0) throw Error("cones: rays " + std::to_string(s.rays) + " < 0");
  if (!(s.light_radius_fraction > 0.0f && std::isfinite(s.light_radius_fraction))) {
    throw Error("cones: light_radius_fraction " + std::to_string(s.light_radius_fraction) + " is not > 0");
  }
}

/// A direction uniform in solid angle within the cone (the distribution the pattern spreads evenly).
Vec3 random_in_cone(const Vec3& axis, float half_angle, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double s = uniform(rng);
  return generalized::cone_direction(axis, half_angle, s, uniform(rng));
}

/// Runs body(y, rng, cost) for every row in parallel; each row has its own generator (seed and row), so the image does
/// not depend on the thread count.
template <class Body>
void for_rows(const ConeEffectSettings& s, TraversalStats& total, const Body& body) {
  std::mutex merge;
  tbb::parallel_for(tbb::blocked_range<int>(0, s.height), [&](const tbb::blocked_range<int>& rows) {
    TraversalStats cost;
    for (int y = rows.begin(); y != rows.end(); ++y) {
      std::mt19937_64 rng(s.seed * 0x9E3779B97F4A7C15ull + std::uint64_t(y));
      body(y, rng, cost);
    }
    const std::lock_guard<std::mutex> lock(merge);
    total += cost;
  });
}

std::uint8_t shadow_grey(float unblocked, float cosine) {
  return encode_srgb(0.05 + 0.75 * double(unblocked) * double(std::max(cosine, 0.0f)));
}

}  // namespace

ConeEffect parse_cone_effect(std::string_view text) {
  if (text == "shadows") return ConeEffect::soft_shadows;
  if (text == "aa") return ConeEffect::anti_aliasing;
  throw Error("unknown cone effect '" + std::string(text) + "' (known: shadows, aa)");
}

ConeEffectResult render_cone_effect(const Accelerator& accel, const Scene& scene, const Camera& camera,
                                    const ConeEffectSettings& s) {
  check(s);
  std::unique_ptr<generalized::GeneralizedRays> cones;
  if (s.rays == 0) cones = generalized::make_generalized_rays(accel, scene);
  const generalized::ConeQueryOptions query{.samples = s.cone_samples, .coverage = s.coverage};
  const CameraFrame frame = camera.frame(s.width, s.height);
  ConeEffectResult result;
  result.image = Image::filled(s.width, s.height, kBackground);
  const auto start = std::chrono::steady_clock::now();
  if (s.effect == ConeEffect::anti_aliasing) {
    for_rows(s, result.cost, [&](int y, std::mt19937_64& rng, TraversalStats& cost) {
      for (int x = 0; x < s.width; ++x) {
        const Ray center = frame.ray(x, y);
        const Vec3 corner = frame.ray_at(float(x), float(y)).direction;
        const float half_angle = std::acos(std::clamp(dot(center.direction, corner), -1.0f, 1.0f)) * 1.0001f;
        double r = 0, g = 0, b = 0, background;
        if (cones) {
          const auto seen = cones->cone_visibility(Cone{frame.eye, center.direction, half_angle}, query, &cost);
          for (const auto& v : seen.visible) {
            const Hit hit{v.distance, v.prim_id, 0.0f, 0.0f};
            const Rgb c = normal_colour(geometric_normal(scene, center, hit));
            r += v.coverage * c.r;
            g += v.coverage * c.g;
            b += v.coverage * c.b;
          }
          background = 1.0 - seen.blocked;
        } else {
          int misses = 0;
          for (int k = 0; k < s.rays; ++k) {
            const Ray ray{frame.eye, 0.0f, random_in_cone(center.direction, half_angle, rng)};
            const Hit hit = accel.intersect(ray, cost);
            if (!hit.found()) {
              ++misses;
              continue;
            }
            const Rgb c = normal_colour(geometric_normal(scene, ray, hit));
            r += double(c.r) / s.rays;
            g += double(c.g) / s.rays;
            b += double(c.b) / s.rays;
          }
          background = double(misses) / s.rays;
        }
        r += background * kBackground.r;
        g += background * kBackground.g;
        b += background * kBackground.b;
        const auto channel = [](double v) { return std::uint8_t(std::lround(std::clamp(v, 0.0, 255.0))); };
        result.image.set(x, y, {channel(r), channel(g), channel(b)});
      }
    });
    result.queries = std::uint64_t(s.width) * std::uint64_t(s.height) * std::uint64_t(cones ? 1 : s.rays);
  } else {
    const Light light = default_lights(scene.bounds(), camera, 1, s.light_radius_fraction).front();
    const float offset = 1e-4f * std::max(length(scene.bounds().extent()), 1e-30f);
    std::vector<std::uint64_t> counts(std::size_t(s.height), 0);
    for_rows(s, result.cost, [&](int y, std::mt19937_64& rng, TraversalStats& cost) {
      for (int x = 0; x < s.width; ++x) {
        const Ray ray = frame.ray(x, y);
        const Hit hit = accel.intersect(ray);
        if (!hit.found()) continue;
        Vec3 n = geometric_normal(scene, ray, hit);
        if (dot(n, ray.direction) > 0.0f) n = -n;
        const Vec3 p = ray.origin + ray.direction * hit.t + n * offset;
        const Vec3 to_light = light.position - p;
        const float distance = length(to_light);
        const float cosine = dot(n, to_light) / distance;
        float unblocked = 1.0f;
        if (cosine > 0.0f && distance > light.radius) {
          const Vec3 axis = to_light / distance;
          const float half_angle = std::asin(light.radius / distance);
          const float reach = std::sqrt(std::max(0.0f, distance * distance - light.radius * light.radius));
          if (cones) {
            unblocked = 1.0f - cones->cone_visibility(Cone{p, axis, half_angle, 0.0f, reach}, query, &cost).blocked;
            ++counts[std::size_t(y)];
          } else {
            int open = 0;
            for (int k = 0; k < s.rays; ++k) {
              open += accel.occluded(Ray{p, 0.0f, random_in_cone(axis, half_angle, rng), reach}, cost) ? 0 : 1;
            }
            unblocked = float(open) / float(s.rays);
            counts[std::size_t(y)] += std::uint64_t(s.rays);
          }
        }
        const std::uint8_t grey = shadow_grey(unblocked, cosine);
        result.image.set(x, y, {grey, grey, grey});
      }
    });
    for (const std::uint64_t c : counts) result.queries += c;
  }
  result.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace rayaccel
