// The oracle of the instanced tests: brute force over the flattened scene (every instance's vertices mapped in
// double and rounded to float), a random scene of three geometries (rotated, non-uniformly scaled, mirrored and
// translated instances) and random rays compared under the rule below. Shared by the bottom-level and top-level tests.
//
// The rule, since an instanced ray and a flattened triangle round differently (see instanced_accelerator.h):
// - Both answers name the same surface point up to rounding: |t - t_ref| * |d| <= kTolerance * R / max(|cos|, 0.05),
//   R = |origin| + the scene's radius, cos the angle between the ray and the reference triangle, and kTolerance =
//   2^-24 * 64 (a few roundings, each amplified by the transforms' condition number, at most 4 here).
// - Found or not, and which (instance, primitive), must agree, except within the edge band: a disagreement where the
//   hit that one side found lies within 1e-4 (in barycentrics) of an edge of its triangle. Those are counted and must
//   stay under 1% of the rays. A ray aimed at a triangle's interior (barycentrics >= 0.1) that the reference finds
//   unobstructed may disagree only where the instanced side found another triangle near its edge.
// - Rays aimed through a vertex of an instance of the closed sphere, towards its center, must hit (no gap at a vertex
//   inside one instance: the bottom level's watertight guarantee on the one mapped ray).
// Disabled instances (set_enabled()) are compared against the flattened scene of the enabled ones alone, and a
// refitted top level (update_top()) against the flattened moved scene.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "rayaccel/accel/registry.h"
#include "rayaccel/instance/flatten.h"
#include "rayaccel/instance/instanced_accelerator.h"
#include "rayaccel/scene/builtin_scenes.h"

namespace rayaccel::instanced_test {

constexpr double kTolerance = 64.0 * 0x1p-24;
constexpr float kEdgeBand = 1e-4f;  // in barycentrics
constexpr std::uint32_t kSphere = 0;  // geometry 0: a closed sphere around the origin

inline InstancedScene make_scene(std::uint32_t instance_count, std::uint32_t seed) {
  InstancedScene scene;
  scene.add_geometry(make_builtin_scene("sphere", {{"level", "1"}}));
  scene.add_geometry(make_builtin_scene("sierpinski", {{"level", "2"}}));
  scene.add_geometry(make_builtin_scene("soup", {{"count", "60"}, {"seed", "3"}}));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_real_distribution<double> scale(0.5, 2.0);
  for (std::uint32_t i = 0; i < instance_count; ++i) {
    double sx = scale(rng), sy = scale(rng), sz = scale(rng);
    if (i % 3 == 1) sy = -sy;  // every third a mirror (negative determinant)
    if (i % 4 == 0) sy = sz = sx;  // and some uniform scales
    const Affine3 m = Affine3::translation(10.0 * unit(rng), 10.0 * unit(rng), 10.0 * unit(rng)) *
                      Affine3::rotation({unit(rng), unit(rng), unit(rng) + 2.0f}, std::numbers::pi * unit(rng)) *
                      Affine3::scaling(sx, sy, sz);
    scene.add_instance(i % scene.geometry_count(), m, 1000 + i);
  }
  return scene;
}

inline float edge_distance(float u, float v) { return std::min({u, v, 1.0f - u - v}); }

struct Tally {
  int rays = 0;
  int edge_band = 0;
  int ties = 0;
};

class Comparison {
 public:
  explicit Comparison(const InstancedScene& scene) : flat_(flatten(scene)), reference_(make_accelerator("brute_force")) {
    reference_->build(flat_.scene);
    const AABB& b = flat_.scene.bounds();
    radius_ = std::max(length(b.lo), length(b.hi));
  }

  /// Checks one ray. A ray aimed at an interior point of flat primitive `target` whose reference hit is that
  /// primitive may not fall in the edge band.
  void check(const InstancedAccelerator& accel, const Ray& ray, std::uint32_t target, Tally& tally) const {
    ++tally.rays;
    const Hit ref = reference_->intersect(ray);
    const bool interior = ref.found() && ref.prim_id == target;
    const InstanceHit got = accel.intersect(ray);
    EXPECT_EQ(accel.occluded(ray), got.found());
    // A disagreement is allowed where a hit one side found (other than the unobstructed target) is near an edge.
    const bool near_edge = (ref.found() && !interior && edge_distance(ref.u, ref.v) < kEdgeBand) ||
                           (got.found() && edge_distance(got.u, got.v) < kEdgeBand);
    if (ref.found() != got.found()) {
      EXPECT_TRUE(near_edge) << describe(ray, ref, got);
      ++tally.edge_band;
      return;
    }
    if (!ref.found()) return;
    // The reference's own instance numbers its primitives; the structure's number for it may differ (a subset).
    const std::uint32_t reference_instance = flat_.instance_of(ref.prim_id);
    const std::uint32_t ref_instance = accel_instance(reference_instance);
    const auto ref_prim = static_cast<std::uint32_t>(ref.prim_id - flat_.first_prim.at(reference_instance));
    const bool same = ref_instance == got.instance && ref_prim == got.prim_id;
    const bool close = std::fabs(double(got.t) - double(ref.t)) <= allowed_t_error(ray, ref);
    if (same) {
      EXPECT_TRUE(close) << describe(ray, ref, got);
      EXPECT_EQ(got.instance_id, 1000 + got.instance);
      EXPECT_EQ(got.geom_id, accel_geometry(got.instance));
    } else if (close) {
      ++tally.ties;  // two surfaces at the same point (an edge shared inside an instance, or crossing instances)
    } else {
      EXPECT_TRUE(near_edge) << describe(ray, ref, got);
      ++tally.edge_band;
    }
  }

  const FlattenedScene& flat() const { return flat_; }
  double radius() const { return radius_; }
  void set_geometry_of(std::vector<std::uint32_t> geometry) { geometry_ = std::move(geometry); }
  /// When the reference scene holds a subset of the structure's instances: its instance i is the structure's
  /// instance_map[i].
  void set_instance_map(std::vector<std::uint32_t> instance_map) { instance_map_ = std::move(instance_map); }

 private:
  std::uint32_t accel_instance(std::uint32_t reference_instance) const {
    return instance_map_.empty() ? reference_instance : instance_map_.at(reference_instance);
  }

  std::uint32_t accel_geometry(std::uint32_t instance) const { return geometry_.at(instance); }

  double allowed_t_error(const Ray& ray, const Hit& ref) const {
    const auto tri = flat_.scene.triangle(ref.prim_id);
    const Vec3 n = cross(tri[1] - tri[0], tri[2] - tri[0]);
    const double d = length(ray.direction);
    const double cosine = std::fabs(dot(n, ray.direction)) / (double(length(n)) * d);
    return kTolerance * (double(length(ray.origin)) + radius_) / (d * std::max(cosine, 0.05));
  }

  std::string describe(const Ray& ray, const Hit& ref, const InstanceHit& got) const {
    auto vec = [](const Vec3& v) {
      return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
    };
    return "ray " + vec(ray.origin) + " -> " + vec(ray.direction) + ": reference " +
           (ref.found() ? "flat prim " + std::to_string(ref.prim_id) + " t " + std::to_string(ref.t) : "miss") +
           ", instanced " +
           (got.found() ? "instance " + std::to_string(got.instance) + " prim " + std::to_string(got.prim_id) + " t " +
                              std::to_string(got.t)
                        : "miss");
  }

  FlattenedScene flat_;
  std::unique_ptr<Accelerator> reference_;
  double radius_ = 0.0;
  std::vector<std::uint32_t> geometry_;
  std::vector<std::uint32_t> instance_map_;
};

inline std::vector<std::uint32_t> geometries_of(const InstancedScene& scene) {
  std::vector<std::uint32_t> out;
  for (const Instance& instance : scene.instances()) out.push_back(instance.geometry);
  return out;
}

inline Vec3 random_point(std::mt19937& rng, float half) {
  std::uniform_real_distribution<float> d(-half, half);
  return {d(rng), d(rng), d(rng)};
}

/// Random rays, and rays from random points at interior points of random triangles (barycentrics >= 0.1). The
/// reference is `scene` flattened; `accel` may hold more instances (`accel_scene`, with `instance_map` naming which
/// of them the reference's are).
inline Tally compare_rays(const InstancedScene& scene, const InstancedAccelerator& accel, std::uint32_t seed,
                   int rays_per_kind = 600, const InstancedScene* accel_scene = nullptr,
                   std::vector<std::uint32_t> instance_map = {}) {
  Comparison comparison(scene);
  comparison.set_geometry_of(geometries_of(accel_scene ? *accel_scene : scene));
  comparison.set_instance_map(std::move(instance_map));
  std::mt19937 rng(seed);
  Tally tally;
  for (int i = 0; i < rays_per_kind; ++i) {
    Ray ray;
    ray.origin = random_point(rng, 20.0f);
    ray.direction = random_point(rng, 1.0f);
    comparison.check(accel, ray, kInvalidPrimId, tally);
  }
  std::uniform_real_distribution<float> weight(0.1f, 1.0f);
  const Scene& flat = comparison.flat().scene;
  for (int i = 0; i < rays_per_kind; ++i) {
    const std::uint32_t prim = std::uniform_int_distribution<std::uint32_t>(0, flat.primitive_count() - 1)(rng);
    if (!flat.is_valid(prim)) continue;
    const auto tri = flat.triangle(prim);
    const float a = weight(rng), b = weight(rng), c = weight(rng);
    const Vec3 target = (tri[0] * a + tri[1] * b + tri[2] * c) / (a + b + c);
    Ray ray;
    ray.origin = random_point(rng, 20.0f);
    ray.direction = target - ray.origin;
    comparison.check(accel, ray, prim, tally);
  }
  EXPECT_LE(tally.edge_band, tally.rays / 100) << "edge-band disagreements out of " << tally.rays << " rays";
  return tally;
}

/// The reference for disabled instances: the scene of `scene`'s enabled instances alone, and for each of its instances
/// the number of that instance in `scene` (compare_rays()'s instance_map).
struct EnabledOnly {
  InstancedScene scene;
  std::vector<std::uint32_t> instance_map;
};

/// Disables every third instance of `scene` in `accel` (checking is_enabled()) and returns the reference.
inline EnabledOnly disable_every_third_instance(const InstancedScene& scene, InstancedAccelerator& accel) {
  EnabledOnly out;
  for (std::uint32_t g = 0; g < scene.geometry_count(); ++g) {
    out.scene.add_geometry(std::make_shared<const Scene>(scene.geometry(g)));
  }
  for (std::uint32_t i = 0; i < scene.instance_count(); ++i) {
    const bool enabled = i % 3 != 0;
    accel.set_enabled(i, enabled);
    EXPECT_EQ(accel.is_enabled(i), enabled);
    if (!enabled) continue;
    const Instance& instance = scene.instance(i);
    out.scene.add_instance(instance.geometry, instance.transform, instance.instance_id);
    out.instance_map.push_back(i);
  }
  return out;
}

}  // namespace rayaccel::instanced_test
