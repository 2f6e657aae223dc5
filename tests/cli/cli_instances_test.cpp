// End-to-end tests of `rayaccel trace --instances`: a glTF written here places one closed mesh by three nodes (read
// as one geometry and three instances, checked first), a builtin sphere is added beside it with --geometry, and the
// .ihits and .occ files the tool writes equal, byte for byte, what the library's InstancedAccelerator answers over
// the same scene. Bad combinations of options fail with a usage error naming them.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "../instance/gltf_file.h"
#include "cli_runner.h"
#include "rayaccel/instance/import_instanced.h"
#include "rayaccel/instance/instance_hits_file.h"
#include "rayaccel/instance/instanced_accelerator.h"
#include "rayaccel/scene/import.h"
#include "rayaccel/scene/ray_io.h"

namespace rayaccel {
namespace {

using testing::fresh_directory;
using testing::run_cli;

constexpr const char* kSphere = "builtin:sphere:level=2";

struct InstancedCase {
  std::filesystem::path dir, gltf, rays;
};

/// A closed tetrahedron placed by three nodes (one the rotated child of a translated parent), and rays from around
/// the scene aimed at it and at the sphere beside it.
InstancedCase make_case() {
  InstancedCase c;
  c.dir = fresh_directory("instances");
  c.gltf = c.dir / "three_tetrahedra.gltf";
  const float a[3] = {1, 1, 1}, b[3] = {1, -1, -1}, d[3] = {-1, 1, -1}, e[3] = {-1, -1, 1};
  std::vector<float> positions;
  for (const auto& tri : {std::array{a, b, d}, std::array{a, e, b}, std::array{a, d, e}, std::array{b, e, d}}) {
    for (const float* p : tri) positions.insert(positions.end(), p, p + 3);
  }
  testing::write_gltf(c.gltf, positions, "[0, 1]", R"([
    {"mesh": 0, "translation": [3, 0, 0]},
    {"mesh": 0, "translation": [-3, 0, 0], "children": [2]},
    {"mesh": 0, "translation": [0, 3, 0], "rotation": [0, 0, 0.3826834, 0.9238795]}
  ])");
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<Ray> rays(3000);
  const Vec3 targets[] = {{3, 0, 0}, {-3, 0, 0}, {-3, 3, 0}, {0, 0, 0}};
  for (std::size_t i = 0; i < rays.size(); ++i) {
    rays[i].origin = Vec3{u(rng), u(rng), u(rng)} * 12.0f;
    rays[i].direction = targets[i % 4] + Vec3{u(rng), u(rng), u(rng)} * 1.5f - rays[i].origin;
  }
  c.rays = c.dir / "scene.rays";
  write_rays(c.rays, rays);
  return c;
}

/// What the library answers: the same scene, the same bottom spec.
InstancedScene library_scene(const InstancedCase& c) {
  InstancedScene scene = import_instanced_scene(c.gltf);
  scene.add_instance(scene.add_geometry(load_scene(kSphere)), Affine3::identity());
  return scene;
}

TEST(CliTraceInstances, IhitsAndOccEqualTheLibrarysAnswers) {
#ifndef RAYACCEL_TEST_WITH_ASSIMP
  GTEST_SKIP() << "built without assimp: glTF files are not read";
#endif
  const InstancedCase c = make_case();
  const InstancedScene scene = library_scene(c);
  ASSERT_EQ(scene.geometry_count(), 2u) << "assimp should read the reused mesh once";
  ASSERT_EQ(scene.instance_count(), 4u);
  EXPECT_EQ(scene.geometry(0).primitive_count(), 4u);

  const auto out = c.dir / "out.ihits";
  const auto result = run_cli({"trace", c.gltf.string(), c.rays.string(), "--instances", "--geometry", kSphere,
                               "--accel", "bvh", "--repeat", "1", "--out", out.string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  InstancedAccelerator accel({"bvh"});
  accel.build(scene);
  const std::vector<Ray> rays = read_rays(c.rays);
  std::vector<InstanceHit> expected(rays.size());
  accel.intersect(rays, expected);

  const std::string bytes = testing::read_file(out);
  ASSERT_EQ(bytes.size(), rays.size() * sizeof(InstanceHitRecord));
  std::size_t found = 0, per_geometry[2] = {0, 0};
  for (std::size_t i = 0; i < rays.size(); ++i) {
    InstanceHitRecord got;
    std::memcpy(&got, bytes.data() + i * sizeof(InstanceHitRecord), sizeof(got));
    const InstanceHit& e = expected[i];
    const InstanceHitRecord want = to_record(e);
    EXPECT_EQ(std::memcmp(&got, &want, sizeof(got)), 0)
        << "ray " << i << ": got t=" << got.t << " prim " << got.prim_id << " geometry " << got.geom_id
        << " instance " << got.instance_id << ", expected t=" << e.t << " prim " << e.prim_id << " geometry "
        << e.geom_id << " instance " << e.instance_id;
    if (e.found()) {
      ++found;
      ++per_geometry[e.geom_id];
    } else {
      EXPECT_EQ(got.geom_id, 0xFFFFFFFFu);
      EXPECT_EQ(got.instance_id, 0xFFFFFFFFu);
      EXPECT_EQ(got.u, 0.0f);
    }
  }
  EXPECT_GT(per_geometry[0], rays.size() / 10) << "the instances should be hit";
  EXPECT_GT(per_geometry[1], rays.size() / 20) << "the geometry beside them should be hit";
  EXPECT_LT(found, rays.size()) << "some rays should miss";

  const nlohmann::json summary = nlohmann::json::parse(result.out);
  EXPECT_EQ(summary["geometries"], 2);
  EXPECT_EQ(summary["instances"], 4);
  EXPECT_EQ(summary["bottom"], "bvh");
  EXPECT_EQ(summary["rays"], rays.size());
  EXPECT_EQ(summary["hit_count"], found);
  EXPECT_EQ(summary["primitives"], scene.flattened_primitive_count());

  const auto occ = c.dir / "out.occ";
  const auto occlusion = run_cli({"trace", c.gltf.string(), c.rays.string(), "--instances", "--geometry", kSphere,
                                  "--occlusion", "--repeat", "1", "--out", occ.string()});
  ASSERT_EQ(occlusion.exit_code, 0) << occlusion.err;
  const std::vector<std::uint8_t> occluded = read_occlusion(occ);
  ASSERT_EQ(occluded.size(), rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) EXPECT_EQ(occluded[i] != 0, expected[i].found()) << "ray " << i;
}

TEST(CliTraceInstances, BadOptionsAreUsageErrors) {
  const InstancedCase c = make_case();
  const std::string scene = c.gltf.string(), rays = c.rays.string();
  struct Case {
    std::vector<std::string> args;
    std::string mentions;
  };
  const std::vector<Case> cases{
      {{"trace", scene, rays, "--geometry", kSphere}, "--geometry needs --instances"},
      {{"trace", scene, rays, "--instances", "--packets"}, "--packets"},
      {{"trace", scene, rays, "--instances", "--save", (c.dir / "x.bvh").string()}, "--save"},
      {{"trace", scene, rays, "--instances", "--accel", "no_such_structure"}, "no_such_structure"},
      {{"trace", scene, rays, "--instances", "--geometry", (c.dir / "missing.ply").string()}, "missing.ply"},
      {{"trace", (c.dir / "missing.gltf").string(), rays, "--instances"}, "missing.gltf"},
      {{"trace", scene, rays, "--instances", "--repeat", "0"}, "--repeat"},
      {{"trace", scene, rays, "--top", "bvh"}, "--top needs --instances"},
      {{"trace", scene, rays, "--instances", "--top", "no_such_top"}, "no_such_top"},
  };
  for (const Case& bad : cases) {
    const auto result = run_cli(bad.args);
    EXPECT_EQ(result.exit_code, 2) << bad.mentions << ": " << result.err;
    EXPECT_NE(result.err.find(bad.mentions), std::string::npos) << result.err;
  }
}

TEST(CliTraceInstances, ABuiltinSceneIsOneInstance) {
  const InstancedCase c = make_case();
  const auto out = c.dir / "builtin.ihits";
  const auto result = run_cli({"trace", kSphere, c.rays.string(), "--instances", "--repeat", "1", "--out",
                               out.string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json summary = nlohmann::json::parse(result.out);
  EXPECT_EQ(summary["geometries"], 1);
  EXPECT_EQ(summary["instances"], 1);
  EXPECT_EQ(testing::read_file(out).size(), read_rays(c.rays).size() * sizeof(InstanceHitRecord));
}

// --top names the top level: the .ihits equal the library's with that top level.
TEST(CliTraceInstances, TopNamesTheTopLevel) {
  const InstancedCase c = make_case();
  const auto out = c.dir / "top.ihits";
  const auto result = run_cli({"trace", kSphere, c.rays.string(), "--instances", "--top", "kdtree", "--repeat", "1",
                               "--out", out.string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(nlohmann::json::parse(result.out)["top"], "kdtree");
  InstancedScene scene;
  scene.add_instance(scene.add_geometry(load_scene(kSphere)), Affine3::identity());
  InstancedAcceleratorOptions options;
  options.top = "kdtree";
  InstancedAccelerator accel(options);
  accel.build(scene);
  const std::vector<Ray> rays = read_rays(c.rays);
  const std::string bytes = testing::read_file(out);
  ASSERT_EQ(bytes.size(), rays.size() * sizeof(InstanceHitRecord));
  std::size_t found = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const InstanceHit expected = accel.intersect(rays[i]);
    const InstanceHitRecord want = to_record(expected);
    EXPECT_EQ(std::memcmp(bytes.data() + i * sizeof(InstanceHitRecord), &want, sizeof(want)), 0) << "ray " << i;
    found += expected.found() ? 1 : 0;
  }
  EXPECT_GT(found, rays.size() / 20) << "the sphere should be hit";
}

}  // namespace
}  // namespace rayaccel
