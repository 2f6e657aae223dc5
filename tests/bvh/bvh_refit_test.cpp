// Refit after Scene::set_vertices(): a grid mesh deformed by a travelling wave over several frames; after each
// refit every builder's tree must validate and agree with brute force.
#include <gtest/gtest.h>

#include <cmath>

#include "bvh_test_scenes.h"
#include "rayaccel/bvh/bvh.h"

namespace rayaccel {
namespace {

std::vector<Vec3> wave(const std::vector<Vec3>& rest, float phase) {
  std::vector<Vec3> out = rest;
  for (Vec3& v : out) v.y = 0.3f * std::sin(4.0f * v.x + phase) * std::cos(3.0f * v.z - phase);
  return out;
}

class BvhRefit : public ::testing::TestWithParam<BvhBuilder> {};

TEST_P(BvhRefit, WaveFramesAgreeWithBruteForce) {
  const TriangleMesh mesh = bvh_test::grid_mesh(24);
  const std::vector<Vec3> rest = mesh.vertices;
  Scene scene = Scene::from_mesh(mesh, "wave");
  scene.set_vertices(wave(rest, 0.0f));
  BvhOptions config;
  config.builder = GetParam();
  Bvh<AabbVolume> bvh(config);
  bvh.build(scene);
  for (int frame = 1; frame <= 4; ++frame) {
    scene.set_vertices(wave(rest, 0.7f * static_cast<float>(frame)));
    bvh.refit();
    const auto problems = bvh.validate();
    ASSERT_TRUE(problems.empty()) << "frame " << frame << ": " << problems.front();
    bvh_test::expect_agrees_with_brute_force(bvh, scene, bvh_test::random_rays(scene.bounds(), 800, 11 + frame),
                                             std::string(to_string(GetParam())) + " frame " + std::to_string(frame));
  }
}

TEST(BvhRefitErrors, RefitBeforeBuildThrows) {
  Bvh<AabbVolume> bvh;
  EXPECT_THROW(bvh.refit(), Error);
}

INSTANTIATE_TEST_SUITE_P(AllBuilders, BvhRefit,
                         ::testing::Values(BvhBuilder::binned, BvhBuilder::sweep, BvhBuilder::sbvh, BvhBuilder::lbvh,
                                           BvhBuilder::ploc),
                         [](const ::testing::TestParamInfo<BvhBuilder>& param) { return to_string(param.param); });

}  // namespace
}  // namespace rayaccel

namespace rayaccel {
namespace {

/// Long thin triangles, so the SBVH really duplicates references before the refit.
TEST(BvhRefitSbvh, DuplicatedReferencesSurviveRefit) {
  TriangleMesh mesh;
  for (std::uint32_t i = 0; i < 300; ++i) {
    const float o = 0.01f * static_cast<float>(i);
    mesh.vertices.push_back({o, 0, 0});
    mesh.vertices.push_back({o + 1, 1, 1});
    mesh.vertices.push_back({o + 1.002f, 1, 1});
    mesh.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  Scene scene = Scene::from_mesh(mesh, "slivers");
  BvhOptions config;
  config.builder = BvhBuilder::sbvh;
  Bvh<AabbVolume> bvh(config);
  bvh.build(scene);
  double refs = 0;
  for (const auto& s : bvh.build_statistics()) refs = s.name == "references_per_primitive" ? s.value : refs;
  ASSERT_GT(refs, 1.05);
  for (Vec3& v : mesh.vertices) v = Vec3{v.x, v.y + 0.3f * std::sin(3.0f * v.x), v.z};
  scene.set_vertices(mesh.vertices);
  bvh.refit();
  const auto problems = bvh.validate();
  EXPECT_TRUE(problems.empty()) << problems.front();
  bvh_test::expect_agrees_with_brute_force(bvh, scene, bvh_test::random_rays(scene.bounds(), 1500, 61), "sbvh refit");
}

}  // namespace
}  // namespace rayaccel
