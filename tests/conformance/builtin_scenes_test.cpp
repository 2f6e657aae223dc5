// Conformance on the built-in procedural scenes (scene/builtin_scenes.h), generated small: every structure must
// agree with brute force on seeded random rays and camera rays over each.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "oracle.h"
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
    expect_matches_brute_force(*accel, scene, camera_rays(scene.bounds(), 24, 16), scene.name() + " camera rays");
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
