// InstancedAccelerator against the oracle: brute force over the flattened scene (every instance's vertices mapped in
// double and rounded to float), over several bottom-level structures, with rotated, non-uniformly scaled, mirrored
// and translated instances of three geometries.
//
// The oracle and its rule: instanced_comparison.h.
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
#include "instanced_comparison.h"
#include "../conformance/oracle.h"

namespace rayaccel {
namespace {

using namespace instanced_test;

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
  const EnabledOnly enabled_only = disable_every_third_instance(scene, accel);
  compare_rays(enabled_only.scene, accel, 18, 600, &scene, enabled_only.instance_map);
  // The setting survives a top-level rebuild; enabling everything again restores the whole scene.
  accel.rebuild_top();
  compare_rays(enabled_only.scene, accel, 19, 200, &scene, enabled_only.instance_map);
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
                         conformance::spec_test_name);

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
