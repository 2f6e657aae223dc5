// The far-ray reproducers on the shared scenes, and every kind of structure against exact rational arithmetic on far
// and short rays of the bunny, dragon, Sponza and conference room (slow tier).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "../conformance/oracle.h"
#include "../shared_scenes.h"
#include "../conformance/test_scenes.h"
#include "exact_reference.h"
#include "far_rays.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/render/camera.h"
#include "rayaccel/scene/import.h"

namespace rayaccel::exact {
namespace {

std::filesystem::path shared_scene(const std::string& file) { return testing::shared_scenes_dir() / file; }

/// The shared scene's mesh, or an empty one when the file is missing (the test then skips or fails through
/// RAYACCEL_NEED_SHARED_FILE).
TriangleMesh shared_mesh(const std::string& file) {
  const auto path = shared_scene(file);
  return std::filesystem::exists(path) ? import_mesh(path) : TriangleMesh{};
}

std::vector<Ray> camera_rays(const Camera& camera, int width, int height) {
  std::vector<Ray> rays;
  const CameraFrame frame = camera.frame(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) rays.push_back(frame.ray(x, y));
  }
  return rays;
}

std::size_t count_hits(const Accelerator& accel, const std::vector<Ray>& rays) {
  std::size_t hits = 0;
  for (const Ray& r : rays) hits += accel.intersect(r).found() ? 1 : 0;
  return hits;
}

class SlowFarRays : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    bunny_ = new TriangleMesh(shared_mesh("bunny.ply"));
    scene_ = new Scene(Scene::from_mesh(*bunny_, "bunny"));
    reference_ = new ExactReference(*bunny_);
  }
  static void TearDownTestSuite() {
    delete reference_;
    delete scene_;
    delete bunny_;
  }
  static TriangleMesh* bunny_;
  static Scene* scene_;
  static ExactReference* reference_;
};
TriangleMesh* SlowFarRays::bunny_ = nullptr;
Scene* SlowFarRays::scene_ = nullptr;
ExactReference* SlowFarRays::reference_ = nullptr;

// The telephoto render: from 1,000 units with a 0.014 degree field of view the image was empty.
TEST_F(SlowFarRays, TelephotoBunnyFrom1000Units) {
  RAYACCEL_NEED_SHARED_FILE(shared_scene("bunny.ply"));
  ASSERT_GT(bunny_->triangles.size(), 0u);
  Camera camera;
  camera.eye = {0.0f, 0.11f, 1000.0f};
  camera.at = {0.0f, 0.11f, 0.0f};
  camera.fov_degrees = 0.014f;
  const std::vector<Ray> rays = camera_rays(camera, 32, 32);
  const auto exact = exact_hits(*reference_, rays);
  std::size_t exact_hit_rays = 0;
  for (const auto& e : exact) exact_hit_rays += e.empty() ? 0 : 1;
  EXPECT_GT(exact_hit_rays, rays.size() / 8) << "the bunny should fill a good part of the view (a quarter of it)";
  for (const char* spec : {"brute_force", "bvh_wide", "kdtree:builder=sah", "grid"}) {
    auto accel = conformance::build_checked(spec, *scene_);
    EXPECT_EQ(count_hits(*accel, rays), exact_hit_rays) << spec;
    expect_exact_answers(*accel, rays, exact, std::string(spec) + " telephoto");
  }
}

// From (0, 0.1, 300) along -z brute force named a triangle at t = 300.02 instead of 299.95; from z = 1000 it missed;
// from z = 1 with directions (0, 0, -0.003) and (0, 0, -0.001) it misnamed or missed.
TEST_F(SlowFarRays, AxisRaysFromFarAndWithShortDirections) {
  RAYACCEL_NEED_SHARED_FILE(shared_scene("bunny.ply"));
  ASSERT_GT(bunny_->triangles.size(), 0u);
  const std::vector<Ray> rays = {{{0.0f, 0.1f, 300.0f}, 0.0f, {0, 0, -1}, INFINITY},
                                 {{0.0f, 0.1f, 1000.0f}, 0.0f, {0, 0, -1}, INFINITY},
                                 {{0.0f, 0.1f, 1.0f}, 0.0f, {0, 0, -0.003f}, INFINITY},
                                 {{0.0f, 0.1f, 1.0f}, 0.0f, {0, 0, -0.001f}, INFINITY}};
  const auto exact = exact_hits(*reference_, rays);
  auto brute = conformance::build_checked("brute_force", *scene_);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_FALSE(exact[i].empty()) << "ray " << i << " should hit the bunny";
    const Hit hit = brute->intersect(rays[i]);
    EXPECT_EQ(hit.prim_id, exact[i].front().prim_id) << "ray " << i;
  }
  EXPECT_NEAR(brute->intersect(rays[0]).t, 299.95, 0.01);
  expect_exact_answers(*brute, rays, exact, "brute force axis rays");
}

// A closed scan seen from 3,000 times its size with a matching field of view lost every hit; camera rays with
// directions scaled by 1e-3 lost or misnamed 2-20% of them.
TEST_F(SlowFarRays, NarrowViewFrom3000SizesAndShortCameraDirections) {
  RAYACCEL_NEED_SHARED_FILE(shared_scene("bunny.ply"));
  ASSERT_GT(bunny_->triangles.size(), 0u);
  const AABB box = scene_->bounds();
  const float size = length(box.extent());
  Camera far_camera;
  far_camera.at = box.center();
  far_camera.eye = box.center() + Vec3{0.3f, 0.2f, 1.0f} * (3000.0f * size);
  far_camera.fov_degrees = 2.0f * std::atan(0.6f / 3000.0f) * 57.29578f;
  std::vector<Ray> rays = camera_rays(far_camera, 24, 24);
  const auto standard = standard_camera(shared_scene("bunny.ply"));
  ASSERT_TRUE(standard.has_value());
  for (Ray r : camera_rays(*standard, 24, 24)) {
    r.direction = r.direction * 1e-3f;
    rays.push_back(r);
  }
  const auto exact = exact_hits(*reference_, rays);
  for (const std::string spec : {"brute_force", "bvh_wide", "bvh:bv=obb,builder=binned", "octree", "bsp"}) {
    auto accel = conformance::build_checked(spec, *scene_);
    expect_exact_answers(*accel, rays, exact, spec + " far camera and short directions");
  }
}

// A unit sphere mesh was missed from 1e5 units.
TEST(SlowFarRaysSphere, UnitSphereFrom1e5Units) {
  const TriangleMesh mesh = conformance::closed_sphere_mesh(16, 32);
  const Scene scene = Scene::from_mesh(mesh, "sphere");
  conformance::Rng rng(9);
  std::vector<Ray> rays;
  for (int i = 0; i < 64; ++i) {
    const Vec3 from = rng.unit_vector() * 1e5f;
    rays.push_back({from, 0.0f, (rng.unit_vector() * 0.5f) - from, INFINITY});  // toward a point inside
  }
  const auto exact = exact_hits(ExactReference(mesh), rays);
  for (const std::string& spec : conformance::variant_specs()) {
    auto accel = conformance::build_checked(spec, scene);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ASSERT_FALSE(exact[i].empty());
      EXPECT_TRUE(accel->intersect(rays[i]).found()) << spec << ", ray " << i;
    }
    expect_exact_answers(*accel, rays, exact, spec + " sphere from 1e5");
  }
}

/// Every variant but the BVH's bounding-volume x builder grid, of which every volume with the binned builder and every
/// builder with boxes: a far ray's answer rests on the volume's test and the leaves' kernel, which the builder does not
/// change (the conformance tier's ExactFarRays runs all 40 on small scenes; here each costs a build on the bunny).
std::vector<std::string> every_traversal_specs() {
  std::vector<std::string> specs;
  for (const std::string& spec : conformance::variant_specs()) {
    const bool bvh_grid = spec.rfind("bvh:bv=", 0) == 0;
    if (!bvh_grid || spec.find("builder=binned") != std::string::npos || spec.rfind("bvh:bv=aabb,", 0) == 0) {
      specs.push_back(spec);
    }
  }
  return specs;
}

// Every traversal on the bunny, and every kind but one on the larger scenes, on rays from 1 to 1e6 scene sizes away
// with direction lengths from 1e-6 to 1e6.
TEST_F(SlowFarRays, EveryTraversalOnTheBunny) {
  RAYACCEL_NEED_SHARED_FILE(shared_scene("bunny.ply"));
  ASSERT_GT(bunny_->triangles.size(), 0u);
  const std::vector<Ray> rays = far_rays(*bunny_, kSceneSizesAway, kDirectionLengths, 4, 11);
  const auto exact = exact_hits(*reference_, rays);
  const std::vector<std::string> specs = every_traversal_specs();
  ASSERT_EQ(specs.size(), conformance::variant_specs().size() - 28) << "8 volumes x 5 builders -> 8 + 4";
  for (const std::string& spec : specs) {
    auto accel = conformance::build_checked(spec, *scene_);
    expect_exact_answers(*accel, rays, exact, spec + " on the bunny");
  }
}

class SlowFarRaysLargeScene : public ::testing::TestWithParam<std::string> {};

TEST_P(SlowFarRaysLargeScene, EveryKindAgreesWithExactArithmetic) {
  RAYACCEL_NEED_SHARED_FILE(shared_scene(GetParam()));
  const TriangleMesh mesh = shared_mesh(GetParam());
  ASSERT_GT(mesh.triangles.size(), 0u);
  const Scene scene = Scene::from_mesh(mesh, GetParam());
  const std::vector<Ray> rays = far_rays(mesh, kSceneSizesAway, kDirectionLengths, 2, 12);
  const auto exact = exact_hits(ExactReference(mesh), rays);
  // Every kind but the BSP tree (it runs on the bunny above): its build takes minutes on these scenes (6 on the
  // conference room), more than the CI run can spend. (The heap corruption that also kept it out was fixed in
  // 93063df: `rayaccel bench conference.ply --accel bsp` now completes with no mismatch.)
  for (const std::string spec : {"bvh_wide", "bvh_wide:width=4", "kdtree:builder=sah", "grid", "grid2", "octree",
                                 "bvh:bv=sphere,builder=lbvh", "bvh:bv=obb,builder=ploc"}) {
    auto accel = conformance::build_checked(spec, scene);
    expect_exact_answers(*accel, rays, exact, spec + " on " + GetParam());
  }
}

INSTANTIATE_TEST_SUITE_P(SlowShared, SlowFarRaysLargeScene,
                         ::testing::Values("dragon.ply", "crytek_sponza.ply", "conference.ply"),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           return param.param.substr(0, param.param.find('.'));
                         });

}  // namespace
}  // namespace rayaccel::exact
