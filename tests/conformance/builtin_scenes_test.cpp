// Conformance on the built-in procedural scenes (scene/builtin_scenes.h), generated small: every structure must
// agree with brute force on seeded random rays and camera rays over each, and on the secondary rays the benchmarks
// trace (a diffuse bounce and a short shadow ray from each camera-ray hit, leaving the surface as
// render/workloads.h offsets them): rays that start a hair above a surface, where a kernel's rounding in t must
// not let brute force "hit" the plane the ray leaves while box culling rules it out.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "oracle.h"
#include "rayaccel/render/workloads.h"
#include "rayaccel/scene/builtin_scenes.h"
#include "test_scenes.h"

namespace rayaccel::conformance {
namespace {

class BuiltinScenes : public ConformanceTest {};

struct BuiltinCase {
  const char* name;
  std::map<std::string, std::string> params;
};

/// Each scene at a size of one to a few thousand primitives.
const std::vector<Scene>& small_builtin_scenes(const std::vector<BuiltinCase>& cases) {
  static std::map<std::string, std::vector<Scene>> cache;
  auto& scenes = cache[cases.front().name];
  if (scenes.empty()) {
    for (const BuiltinCase& c : cases) scenes.push_back(make_builtin_scene(c.name, c.params));
  }
  return scenes;
}

void expect_matches_on(const std::string& spec, const std::vector<Scene>& scenes) {
  for (const Scene& scene : scenes) {
    ASSERT_GT(scene.primitive_count(), 0u) << scene.name();
    auto accel = build_checked(spec, scene);
    expect_matches_brute_force(*accel, scene, random_rays(scene.bounds(), 600, 61), scene.name() + " random rays");
    const std::vector<Ray> camera = camera_rays(scene.bounds(), 24, 16);
    expect_matches_brute_force(*accel, scene, camera, scene.name() + " camera rays");
    // Secondary rays from a denser camera grid: a few hundred hits per scene.
    const std::vector<Ray> sources = camera_rays(scene.bounds(), 64, 48);
    const std::vector<Hit> source_hits = brute_force_hits(scene, sources);
    const float diagonal = length(scene.bounds().extent());
    expect_matches_brute_force(*accel, scene, diffuse_rays(scene, sources, source_hits, 71),
                               scene.name() + " diffuse rays from camera-ray hits");
    expect_matches_brute_force(*accel, scene, shadow_rays(scene, sources, source_hits, 0.1f * diagonal, 72),
                               scene.name() + " shadow rays from camera-ray hits");
  }
}

TEST_P(BuiltinScenes, ClosedSphereSoupAndSlivers) {
  expect_matches_on(GetParam(), small_builtin_scenes({{"sphere", {{"level", "3"}}},
                                                      {"soup", {{"count", "2000"}}},
                                                      {"slivers", {{"count", "2000"}}}}));
}

TEST_P(BuiltinScenes, SierpinskiMountainAndTeapotStadium) {
  expect_matches_on(GetParam(), small_builtin_scenes({{"sierpinski", {{"level", "4"}}},
                                                      {"mountain", {{"level", "5"}}},
                                                      {"teapot_stadium", {{"segments", "64"}, {"tube", "6"}}}}));
}

TEST_P(BuiltinScenes, SphereflakeSpheres) {
  const auto& scenes = small_builtin_scenes({{"sphereflake", {{"level", "3"}}}});
  ASSERT_EQ(scenes.front().kind(), PrimitiveKind::spheres);
  expect_matches_on(GetParam(), scenes);
}

INSTANTIATE_TEST_SUITE_P(Conformance, BuiltinScenes, ::testing::ValuesIn(variant_specs()), spec_test_name);

}  // namespace
}  // namespace rayaccel::conformance
