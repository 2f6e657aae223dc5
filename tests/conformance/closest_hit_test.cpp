// Conformance: closest hit and any hit of every registered structure against brute force, on seeded random rays and
// camera rays over small triangle scenes, sphere scenes and user-primitive scenes, and on shadow-ray segments.
#include <gtest/gtest.h>

#include "oracle.h"
#include "rayaccel/accel/brute_force.h"
#include "test_scenes.h"

namespace rayaccel::conformance {
namespace {

class ClosestHit : public ConformanceTest {};
class Occlusion : public ConformanceTest {};

TEST_P(ClosestHit, RandomRaysOnSmallScenes) {
  for (const SceneCase& c : small_scene_cases()) {
    auto accel = build_checked(GetParam(), c.scene);
    expect_matches_brute_force(*accel, c.scene, c.rays, c.name + " random rays");
  }
}

TEST_P(ClosestHit, CameraRaysOnSmallScenes) {
  for (const SceneCase& c : small_scene_cases()) {
    auto accel = build_checked(GetParam(), c.scene);
    expect_matches_brute_force(*accel, c.scene, camera_rays(c.scene.bounds(), 32, 24), c.name + " camera rays");
  }
}

TEST_P(ClosestHit, Spheres) {
  const Scene scene = random_sphere_scene(1500, 21);
  auto accel = build_checked(GetParam(), scene);
  expect_matches_brute_force(*accel, scene, random_rays(scene.bounds(), 1000, 22), "spheres random rays");
  expect_matches_brute_force(*accel, scene, camera_rays(scene.bounds(), 32, 24), "spheres camera rays");
}

TEST_P(ClosestHit, UserPrimitives) {
  const Scene scene = user_sphere_scene(1000, 23);
  ASSERT_EQ(scene.kind(), PrimitiveKind::user);
  auto accel = build_checked(GetParam(), scene);
  expect_matches_brute_force(*accel, scene, random_rays(scene.bounds(), 1000, 24), "user primitives random rays");
  expect_matches_brute_force(*accel, scene, camera_rays(scene.bounds(), 32, 24), "user primitives camera rays");
}

/// Shadow rays: segments between two points (t_max = 1 on direction = to - from), some ending exactly on a
/// primitive's vertex, where the t == t_max hit must count.
std::vector<Ray> segment_rays(const Scene& scene, std::size_t count, std::uint64_t seed) {
  Rng rng(seed);
  const AABB box = scene.bounds();
  std::vector<Ray> rays;
  while (rays.size() < count) {
    Ray ray;
    ray.origin = rng.in_box(box);
    Vec3 to = rng.in_box(box);
    if (rng.below(4) == 0 && scene.kind() == PrimitiveKind::triangles) {
      const std::uint32_t id = rng.below(scene.primitive_count());
      if (scene.is_valid(id)) to = scene.triangle(id)[rng.below(3)];
    }
    ray.direction = to - ray.origin;
    if (ray.direction == Vec3{}) continue;
    ray.t_max = 1.0f;
    rays.push_back(ray);
  }
  return rays;
}

TEST_P(Occlusion, MatchesBruteForceAnyHitOnSegments) {
  for (const SceneCase& c : small_scene_cases()) {
    auto accel = build_checked(GetParam(), c.scene);
    BruteForce oracle;
    oracle.build(c.scene);
    const std::vector<Ray> rays = segment_rays(c.scene, 1000, 31);
    const std::vector<Hit> reference = brute_force_hits(c.scene, rays);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(oracle.occluded(rays[i]), reference[i].found()) << "oracle any-hit and closest-hit disagree";
    }
    // Checks occluded() against the oracle's answer, and the closest hits too.
    expect_matches_reference(*accel, c.scene, rays, reference, c.name + " segments");
  }
}

INSTANTIATE_TEST_SUITE_P(Conformance, ClosestHit, ::testing::ValuesIn(variant_specs()), spec_test_name);
INSTANTIATE_TEST_SUITE_P(Conformance, Occlusion, ::testing::ValuesIn(variant_specs()), spec_test_name);

}  // namespace
}  // namespace rayaccel::conformance
