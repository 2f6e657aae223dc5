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
  BvhConfig config;
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
