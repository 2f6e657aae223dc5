// InstancedAccelerator with each top level (option `top`): the TopLevelBvh ("bvh_top") and registry structures built
// over one user primitive per instance, against the oracle of instanced_comparison.h (brute force over the flattened
// scene): closest hits, disabled instances, moved instances after rebuild_top() and update_top().
#include <gtest/gtest.h>

#include <cctype>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/instance/instanced_accelerator.h"
#include "instanced_comparison.h"
#include "../conformance/oracle.h"

namespace rayaccel {
namespace {

using namespace instanced_test;

class ConformanceInstancedTop : public ::testing::TestWithParam<std::string> {};

InstancedAcceleratorOptions with_top(const std::string& top) {
  InstancedAcceleratorOptions options;
  options.top = top;
  return options;
}

TEST_P(ConformanceInstancedTop, MatchesBruteForceOverTheFlattenedScene) {
  const InstancedScene scene = make_scene(36, 7);
  InstancedAccelerator accel(with_top(GetParam()));
  accel.build(scene);
  EXPECT_EQ(accel.top_spec(), GetParam());
  EXPECT_TRUE(accel.validate().empty());
  compare_rays(scene, accel, 11);
}

TEST_P(ConformanceInstancedTop, DisabledInstancesAreNeverHit) {
  const InstancedScene scene = make_scene(36, 17);
  InstancedAccelerator accel(with_top(GetParam()));
  accel.build(scene);
  const EnabledOnly enabled_only = disable_every_third_instance(scene, accel);
  compare_rays(enabled_only.scene, accel, 18, 600, &scene, enabled_only.instance_map);
  for (std::uint32_t i = 0; i < scene.instance_count(); ++i) accel.set_enabled(i, true);
  compare_rays(scene, accel, 20, 200);
}

TEST_P(ConformanceInstancedTop, MovedInstancesAfterRebuildTopAndUpdateTop) {
  InstancedScene scene = make_scene(36, 8);
  InstancedAccelerator accel(with_top(GetParam()));
  accel.build(scene);
  for (std::uint32_t i = 0; i < scene.instance_count(); i += 2) {
    scene.set_transform(i, Affine3::translation(0.0, 5.0, -3.0) * scene.instance(i).transform);
  }
  accel.rebuild_top();
  EXPECT_TRUE(accel.validate().empty());
  compare_rays(scene, accel, 12);
  // Moved again: a top level that can refit (TopLevelBvh, supports_refit()) refits, the others rebuild.
  std::mt19937 rng(3);
  for (std::uint32_t i = 1; i < scene.instance_count(); i += 2) {
    const Vec3 by = random_point(rng, 6.0f);
    scene.set_transform(i, Affine3::translation(by.x, by.y, by.z) * scene.instance(i).transform);
  }
  const bool refits = GetParam() == kTopLevelBvh || make_accelerator(GetParam())->supports_refit();
  EXPECT_EQ(accel.update_top(), refits ? UpdateKind::refitted : UpdateKind::rebuilt);
  EXPECT_TRUE(accel.validate().empty());
  compare_rays(scene, accel, 15);
  scene.add_instance(1, Affine3::translation(0.0, 30.0, 0.0), 1000 + scene.instance_count());
  EXPECT_EQ(accel.update_top(), UpdateKind::rebuilt);
  compare_rays(scene, accel, 16, 300);
}

INSTANTIATE_TEST_SUITE_P(Conformance, ConformanceInstancedTop,
                         ::testing::Values("bvh_top", "bvh_wide", "bvh", "kdtree", "grid"),
                         conformance::spec_test_name);

// Every variant of `rayaccel list --names` takes user primitives, so each serves as the top level (fewer rays each).
TEST(ConformanceInstancedTopAll, EveryVariantAsTopLevel) {
  const InstancedScene scene = make_scene(12, 13);
  for (const std::string& spec : accelerator_variant_names()) {
    SCOPED_TRACE(spec);
    InstancedAccelerator accel(with_top(spec));
    accel.build(scene);
    EXPECT_TRUE(accel.validate().empty());
    compare_rays(scene, accel, 14, 100);
  }
  EXPECT_THROW(InstancedAccelerator(with_top("no_such_structure")), Error);
}

// Embree's comparison structure takes triangles only: as a top level it is refused at build(), by name.
TEST(InstancedTopLevel, AStructureWithoutUserPrimitivesIsRefusedByName) {
  if (!has_accelerator("embree")) GTEST_SKIP() << "embree was not found at build time";
  const InstancedScene scene = make_scene(4, 1);
  InstancedAccelerator accel(with_top("embree"));
  try {
    accel.build(scene);
    ADD_FAILURE() << "embree was accepted as a top level";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("top level 'embree'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rayaccel
