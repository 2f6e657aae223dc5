// InstancedAccelerator against the oracle: brute force over the flattened scene (every instance's vertices mapped in
// double and rounded to float), over several bottom-level structures, with rotated, non-uniformly scaled, mirrored
// and translated instances of three geometries.
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
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/instance/flatten.h"
#include "rayaccel/instance/instanced_accelerator.h"
#include "rayaccel/scene/builtin_scenes.h"

namespace rayaccel {
namespace {

constexpr double kTolerance = 64.0 * 0x1p-24;
constexpr float kEdgeBand = 1e-4f;  // in barycentrics
constexpr std::uint32_t kSphere = 0;  // geometry 0: a closed sphere around the origin

InstancedScene make_scene(std::uint32_t instance_count, std::uint32_t seed) {
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

float edge_distance(float u, float v) { return std::min({u, v, 1.0f - u - v}); }

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
    const std::uint32_t ref_instance = accel_instance(flat_.instance_of(ref.prim_id));
    const auto ref_prim = static_cast<std::uint32_t>(ref.prim_id - flat_.first_prim[ref_instance]);
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

std::vector<std::uint32_t> geometries_of(const InstancedScene& scene) {
  std::vector<std::uint32_t> out;
  for (const Instance& instance : scene.instances()) out.push_back(instance.geometry);
  return out;
}

Vec3 random_point(std::mt19937& rng, float half) {
  std::uniform_real_distribution<float> d(-half, half);
  return {d(rng), d(rng), d(rng)};
}

/// Random rays, and rays from random points at interior points of random triangles (barycentrics >= 0.1). The
/// reference is `scene` flattened; `accel` may hold more instances (`accel_scene`, with `instance_map` naming which
/// of them the reference's are).
Tally compare_rays(const InstancedScene& scene, const InstancedAccelerator& accel, std::uint32_t seed,
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

class ConformanceInstanced : public ::testing::TestWithParam<std::string> {};

TEST_P(ConformanceInstanced, MatchesBruteForceOverTheFlattenedScene) {
  const InstancedScene scene = make_scene(36, 7);
  InstancedAccelerator accel({GetParam()});
  accel.build(scene);
  EXPECT_TRUE(accel.validate().empty());
  const Tally tally = compare_rays(scene, accel, 11);
  RecordProperty("edge_band", tally.edge_band);
  RecordProperty("ties", tally.ties);
}

TEST_P(ConformanceInstanced, MovedInstancesAfterRebuildTop) {
  InstancedScene scene = make_scene(36, 8);
  InstancedAccelerator accel({GetParam()});
  accel.build(scene);
  for (std::uint32_t i = 0; i < scene.instance_count(); i += 2) {
    scene.set_transform(i, Affine3::translation(0.0, 5.0, -3.0) * scene.instance(i).transform);
  }
  accel.rebuild_top();
  EXPECT_TRUE(accel.validate().empty());
  compare_rays(scene, accel, 12);
}

TEST_P(ConformanceInstanced, RefittedTopLevelAfterMoves) {
  InstancedScene scene = make_scene(36, 8);
  InstancedAccelerator accel({GetParam()});
  accel.build(scene);
  std::mt19937 rng(3);
  for (std::uint32_t i = 0; i < scene.instance_count(); i += 2) {
    const Vec3 by = random_point(rng, 6.0f);
    scene.set_transform(i, Affine3::translation(by.x, by.y, by.z) *
                               Affine3::rotation({0.0f, 1.0f, 0.5f}, 0.3 * (i + 1)) * scene.instance(i).transform);
  }
  const std::uint32_t nodes = accel.top().node_count();
  EXPECT_EQ(accel.update_top(), UpdateKind::refitted);
  EXPECT_EQ(accel.top().node_count(), nodes);
  EXPECT_TRUE(accel.validate().empty());
  compare_rays(scene, accel, 15);
  // An instance added since the build: the tree must change, so update_top() rebuilds.
  scene.add_instance(1, Affine3::translation(0.0, 30.0, 0.0), 1000 + scene.instance_count());
  EXPECT_EQ(accel.update_top(), UpdateKind::rebuilt);
  EXPECT_TRUE(accel.validate().empty());
  compare_rays(scene, accel, 16, 300);
}

TEST_P(ConformanceInstanced, DisabledInstancesAreNeverHit) {
  const InstancedScene scene = make_scene(36, 17);
  InstancedAccelerator accel({GetParam()});
  accel.build(scene);
  // The reference: the same geometries with the enabled instances alone.
  InstancedScene enabled_only;
  for (std::uint32_t g = 0; g < scene.geometry_count(); ++g) {
    enabled_only.add_geometry(std::make_shared<const Scene>(scene.geometry(g)));
  }
  std::vector<std::uint32_t> instance_map;
  for (std::uint32_t i = 0; i < scene.instance_count(); ++i) {
    const bool enabled = i % 3 != 0;
    accel.set_enabled(i, enabled);
    EXPECT_EQ(accel.is_enabled(i), enabled);
    if (!enabled) continue;
    const Instance& instance = scene.instance(i);
    enabled_only.add_instance(instance.geometry, instance.transform, instance.instance_id);
    instance_map.push_back(i);
  }
  compare_rays(enabled_only, accel, 18, 600, &scene, instance_map);
  // The setting survives a top-level rebuild; enabling everything again restores the whole scene.
  accel.rebuild_top();
  compare_rays(enabled_only, accel, 19, 200, &scene, instance_map);
  for (std::uint32_t i = 0; i < scene.instance_count(); ++i) accel.set_enabled(i, true);
  compare_rays(scene, accel, 20, 200);
  EXPECT_THROW(accel.set_enabled(scene.instance_count(), false), Error);
  EXPECT_THROW(static_cast<void>(accel.is_enabled(scene.instance_count())), Error);
}

TEST_P(ConformanceInstanced, RaysThroughVerticesOfAClosedInstanceHitIt) {
  const InstancedScene scene = make_scene(36, 9);
  InstancedAccelerator accel({GetParam()});
  accel.build(scene);
  const Scene& sphere = scene.geometry(kSphere);
  int rays = 0;
  for (std::uint32_t i = 0; i < scene.instance_count(); ++i) {
    const Instance& instance = scene.instance(i);
    if (instance.geometry != kSphere) continue;
    const auto center = instance.transform.apply_point({0.0f, 0.0f, 0.0f});
    for (const Vec3& vertex : sphere.mesh().vertices) {
      const auto through = instance.transform.apply_point(vertex);
      Ray ray;
      for (std::size_t a = 0; a < 3; ++a) {  // from outside, through the vertex, towards the center
        ray.origin[a] = static_cast<float>(center[a] + 3.0 * (through[a] - center[a]));
        ray.direction[a] = static_cast<float>(center[a] - ray.origin[a]);
      }
      ray.t_max = 1.0f;  // up to the center: the sphere's surface is in the way
      EXPECT_TRUE(accel.occluded(ray)) << "instance " << i << ": a ray through a vertex went through the surface";
      const InstanceHit hit = accel.intersect(ray);
      EXPECT_TRUE(hit.found());
      ++rays;
    }
  }
  EXPECT_GT(rays, 100);
}

TEST_P(ConformanceInstanced, BatchesAnswerAsSingleRays) {
  const InstancedScene scene = make_scene(24, 10);
  InstancedAccelerator accel({GetParam()});
  accel.build(scene);
  std::mt19937 rng(5);
  std::vector<Ray> rays(500);
  for (Ray& ray : rays) {
    ray.origin = random_point(rng, 20.0f);
    ray.direction = -ray.origin + random_point(rng, 5.0f);
  }
  rays[3].direction = {0.0f, 0.0f, 0.0f};  // void
  std::vector<InstanceHit> hits(rays.size());
  std::vector<std::uint8_t> occluded(rays.size());
  accel.intersect(rays, hits);
  accel.occluded(rays, occluded);
  int found = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const InstanceHit single = accel.intersect(rays[i]);
    EXPECT_EQ(hits[i].t, single.t);
    EXPECT_EQ(hits[i].instance, single.instance);
    EXPECT_EQ(hits[i].prim_id, single.prim_id);
    EXPECT_EQ(occluded[i] != 0, single.found());
    found += single.found() ? 1 : 0;
  }
  EXPECT_FALSE(hits[3].found());
  EXPECT_GT(found, 50);
  std::vector<InstanceHit> short_output(3);
  EXPECT_THROW(accel.intersect(rays, short_output), Error);
}

INSTANTIATE_TEST_SUITE_P(Conformance, ConformanceInstanced,
                         ::testing::Values("bvh_wide", "bvh", "kdtree", "bvh:bv=obb"),
                         [](const auto& param_info) {
                           std::string name = param_info.param;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

// Any registered structure serves as the bottom level: every name of `rayaccel list --names`, fewer rays each.
TEST(ConformanceInstancedAll, EveryVariantAsBottomLevel) {
  const InstancedScene scene = make_scene(12, 13);
  for (const std::string& spec : accelerator_variant_names()) {
    SCOPED_TRACE(spec);
    InstancedAccelerator accel({spec});
    accel.build(scene);
    EXPECT_TRUE(accel.validate().empty());
    compare_rays(scene, accel, 14, 100);
  }
}

TEST(InstancedScene, BadInstancesAreClearErrors) {
  InstancedScene scene;
  scene.add_geometry(make_builtin_scene("sphere", {{"level", "0"}}));
  try {
    scene.add_instance(1, Affine3::identity());
    FAIL() << "geometry 1 of 1 was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "instance 0: geometry index 1 is out of range (the scene has 1 geometries)");
  }
  try {
    scene.add_instance(0, Affine3::scaling(1.0, 1.0, 0.0));
    FAIL() << "a singular transform was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("instance 0: transform is singular"), std::string::npos) << e.what();
  }
  scene.add_instance(0, Affine3::identity());
  Affine3 inf = Affine3::identity();
  inf(0, 0) = INFINITY;
  EXPECT_THROW(scene.set_transform(0, inf), Error);
  EXPECT_THROW(scene.set_transform(1, Affine3::identity()), Error);
  EXPECT_EQ(scene.instance(0).transform.m, Affine3::identity().m);  // a failed set_transform changes nothing
  EXPECT_THROW(scene.add_geometry(std::shared_ptr<const Scene>()), Error);
  EXPECT_THROW(InstancedAccelerator({"no_such_structure"}), Error);
}

TEST(InstancedScene, EmptyScenesAndEmptyGeometriesMiss) {
  InstancedScene scene;
  InstancedAccelerator accel;
  accel.build(scene);
  Ray ray;
  EXPECT_FALSE(accel.intersect(ray).found());
  EXPECT_FALSE(accel.occluded(ray));
  scene.add_geometry(Scene::from_mesh(TriangleMesh{}, "nothing"));
  scene.add_instance(0, Affine3::identity());
  accel.build(scene);
  EXPECT_FALSE(accel.intersect(ray).found());
  EXPECT_TRUE(accel.validate().empty());
}

}  // namespace
}  // namespace rayaccel
