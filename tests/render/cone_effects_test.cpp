// Soft shadows by analytic cones against the many-ray render of the same integral on a shared scene (the conference
// room, 32 x 32, light radius 5% of the diagonal): RMSE in 8-bit levels against a 512-random-ray reference below 8
// (the reference's own noise is about 2; adding coverages without their overlap, Amanatides' simple rule, measured 19)
// and below that of 16 random rays per shading point (about 10).
#include <gtest/gtest.h>

#include "../shared_scenes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/render/cone_effects.h"
#include "rayaccel/render/image_compare.h"
#include "rayaccel/scene/import.h"

namespace rayaccel {
namespace {

TEST(ConeEffects, AnalyticShadowsAgainstManyRaysOnTheConferenceRoom) {
  const auto file = testing::shared_scenes_dir() / "conference.ply";
  RAYACCEL_NEED_SHARED_FILE(file);
  const Scene scene = load_scene(file.string());
  auto accel = make_accelerator("bvh_wide");
  accel->build(scene);
  const Camera camera = standard_camera(file).value_or(Camera::framing(scene.bounds()));
  ConeEffectSettings settings;
  settings.width = settings.height = 32;
  const auto render = [&](int rays, generalized::ConeCoverage coverage) {
    ConeEffectSettings s = settings;
    s.rays = rays;
    s.coverage = coverage;
    return render_cone_effect(*accel, scene, camera, s);
  };
  const Image reference = render(512, generalized::ConeCoverage::analytic).image;
  const ConeEffectResult analytic = render(0, generalized::ConeCoverage::analytic);
  const double analytic_rmse = compare_images(analytic.image, reference).rmse;
  const double rays_rmse = compare_images(render(16, generalized::ConeCoverage::analytic).image, reference).rmse;
  RecordProperty("analytic_rmse", std::to_string(analytic_rmse));
  RecordProperty("rays16_rmse", std::to_string(rays_rmse));
  EXPECT_LT(analytic_rmse, 8.0);
  EXPECT_LT(analytic_rmse, rays_rmse);
  EXPECT_GT(analytic.queries, 0u);
}

}  // namespace
}  // namespace rayaccel
