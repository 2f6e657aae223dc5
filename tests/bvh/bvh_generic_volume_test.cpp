// The generic volume path of Bvh<BV> (volumes fitted to every hull point of the subtree, not merged from children),
// exercised with a test volume: a box that Bvh cannot recognise as AabbVolume. Every builder must agree
// with brute force, validate, and survive refit and save/load.
#include <gtest/gtest.h>

#include <filesystem>

#include <unistd.h>

#include "bvh_test_scenes.h"
#include "rayaccel/bvh/bvh.h"

namespace rayaccel {
namespace {

/// An axis-aligned box that is not AabbVolume, so Bvh takes the point-fitting path.
struct PointFittedBox {
  static constexpr const char* kName = "pointbox";
  using RayContext = AabbVolume::RayContext;
  AABB box;

  static RayContext prepare(const PreparedRay& ray) { return AabbVolume::prepare(ray); }
  static PointFittedBox fit(std::span<const Vec3> points) { return {AabbVolume::fit(points).box}; }
  bool intersect(const RayContext& c, float t_min, float t_max, float* t_entry) const {
    return AabbVolume{box}.intersect(c, t_min, t_max, t_entry);
  }
  float surface_area() const { return box.surface_area(); }
  AABB bounds() const { return box; }
  bool contains(const Vec3& p) const { return box.contains(p); }
};
static_assert(BoundingVolume<PointFittedBox>);

class BvhGenericVolume : public ::testing::TestWithParam<BvhBuilder> {};

TEST_P(BvhGenericVolume, AgreesWithBruteForceAndValidates) {
  BvhOptions config;
  config.builder = GetParam();
  for (const Scene& scene : {bvh_test::random_soup(1500, 51, 0.3f), bvh_test::coplanar_and_duplicates(52),
                             bvh_test::random_spheres(300, 53)}) {
    Bvh<PointFittedBox> bvh(config);
    bvh.build(scene);
    const auto problems = bvh.validate();
    EXPECT_TRUE(problems.empty()) << problems.front();
    bvh_test::expect_agrees_with_brute_force(bvh, scene, bvh_test::random_rays(scene.bounds(), 1000, 54),
                                             std::string("pointbox ") + to_string(GetParam()));
    for (const auto& s : bvh.build_statistics()) {
      if (s.name == "volume_tightness") {
        EXPECT_DOUBLE_EQ(s.value, 1.0);
      }
    }
  }
}

TEST_P(BvhGenericVolume, RefitAndSaveLoad) {
  BvhOptions config;
  config.builder = GetParam();
  TriangleMesh mesh = bvh_test::grid_mesh(16);
  Scene scene = Scene::from_mesh(mesh, "grid");
  Bvh<PointFittedBox> bvh(config);
  bvh.build(scene);
  for (Vec3& v : mesh.vertices) v.y = 0.2f * std::sin(5.0f * v.x) * v.z;
  scene.set_vertices(mesh.vertices);
  bvh.refit();
  EXPECT_TRUE(bvh.validate().empty());
  bvh_test::expect_agrees_with_brute_force(bvh, scene, bvh_test::random_rays(scene.bounds(), 600, 55), "refit");
  const auto file = std::filesystem::temp_directory_path() /
                    ("rayaccel_pointbox_" + std::to_string(::getpid()) + to_string(GetParam()) + ".bvh");
  bvh.save(file);
  Bvh<PointFittedBox> loaded;
  loaded.load(file, scene);
  std::filesystem::remove(file);
  EXPECT_TRUE(loaded.validate().empty());
  bvh_test::expect_agrees_with_brute_force(loaded, scene, bvh_test::random_rays(scene.bounds(), 600, 56), "loaded");
  Bvh<AabbVolume> wrong_kind;
  bvh.save(file);
  EXPECT_THROW(wrong_kind.load(file, scene), Error);
  std::filesystem::remove(file);
}

INSTANTIATE_TEST_SUITE_P(AllBuilders, BvhGenericVolume,
                         ::testing::Values(BvhBuilder::binned, BvhBuilder::sweep, BvhBuilder::sbvh, BvhBuilder::lbvh,
                                           BvhBuilder::ploc),
                         [](const ::testing::TestParamInfo<BvhBuilder>& param) { return to_string(param.param); });

}  // namespace
}  // namespace rayaccel
