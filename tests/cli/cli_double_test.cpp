// End-to-end tests of `rayaccel trace --precision double`: a sphere mesh 10 m across placed near 1e7 (by a PLY with
// double coordinates, or by a float PLY and --offset), rays in .rays64; the .hits64 / .occ files equal the library's
// double brute force, the summary line says so, and the options the double path lacks are refused by name.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../double/double_test_rays.h"
#include "cli_runner.h"
#include "small_case.h"
#include "rayaccel/double/double_accelerator.h"
#include "rayaccel/double/double_scene.h"
#include "rayaccel/scene/builtin_scenes.h"
#include "rayaccel/scene/ray_io.h"

namespace rayaccel {
namespace {

using testing::fresh_directory;
using testing::last_nonempty_line;
using testing::write_ply;
using testing::run_cli;

TriangleMesh sphere_mesh() { return make_builtin_scene("sphere", {{"level", "3"}, {"radius", "10"}}).mesh(); }

/// The offset as text and as the double the CLI must read from it (each number correctly rounded).
const char* const kOffsetText = "10000000.25,12000000.4,-9000000.1";
const DVec3 kOffset{10000000.25, 12000000.4, -9000000.1};

/// Rays from 30 m away aimed at vertices, edge midpoints and centres, and a few that miss or stop short.
std::vector<RayD> case_rays(const TriangleMeshD& mesh) {
  std::vector<RayD> rays = testing::aimed_rays(mesh, 300, 30.0, 21);
  for (std::size_t i = 0; i < rays.size(); i += 7) rays[i].direction = rays[i].direction * -1.0;  // away: a miss
  for (std::size_t i = 3; i < rays.size(); i += 11) rays[i].t_max = 0.5;                           // stops short
  return rays;
}

/// The library's double brute force: closest hits, or occlusion.
std::vector<HitD> brute_force_hits(const TriangleMeshD& mesh, const std::vector<RayD>& rays) {
  const DoubleScene scene(mesh);
  auto oracle = make_double_accelerator("brute_force");
  oracle->build(scene);
  std::vector<HitD> hits(rays.size());
  oracle->intersect(rays, hits);
  return hits;
}

void expect_same_hits(const std::vector<HitD>& got, const std::vector<HitD>& expected, bool same_prim) {
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].t, expected[i].t) << "ray " << i;
    EXPECT_EQ(got[i].found(), expected[i].found()) << "ray " << i;
    if (same_prim) {
      EXPECT_EQ(got[i].prim_id, expected[i].prim_id) << "ray " << i;
      EXPECT_EQ(got[i].u, expected[i].u) << "ray " << i;
      EXPECT_EQ(got[i].v, expected[i].v) << "ray " << i;
    }
  }
}

TEST(CliTraceDouble, DoublePlyFarAwayEqualsTheLibrarysDoubleBruteForce) {
  const auto dir = fresh_directory("double");
  const TriangleMeshD mesh = to_double_mesh(sphere_mesh(), kOffset);
  write_ply(dir / "far.ply", mesh, "double");
  const std::vector<RayD> rays = case_rays(mesh);
  write_rays_d(dir / "far.rays64", rays);
  const std::vector<HitD> expected = brute_force_hits(mesh, rays);

  // Brute force: the same records, byte for byte; the BVH: the same t and hit/miss (a tie may name another triangle).
  const auto brute = run_cli({"trace", (dir / "far.ply").string(), (dir / "far.rays64").string(), "--precision",
                              "double", "--accel", "brute_force", "--repeat", "1", "--out",
                              (dir / "bf.hits64").string()});
  ASSERT_EQ(brute.exit_code, 0) << brute.err;
  write_hits_d(dir / "expected.hits64", expected);
  EXPECT_EQ(testing::read_file(dir / "bf.hits64"), testing::read_file(dir / "expected.hits64"));
  const auto bvh = run_cli({"trace", (dir / "far.ply").string(), (dir / "far.rays64").string(), "--precision",
                            "double", "--accel", "bvh:builder=sweep,leaf_size=2", "--repeat", "2", "--out",
                            (dir / "bvh.hits64").string()});
  ASSERT_EQ(bvh.exit_code, 0) << bvh.err;
  expect_same_hits(read_hits_d(dir / "bvh.hits64"), expected, false);

  std::size_t found = 0;
  for (const HitD& h : expected) found += h.found() ? 1 : 0;
  EXPECT_GT(found, rays.size() / 2);
  EXPECT_LT(found, rays.size());
  const nlohmann::json summary = nlohmann::json::parse(last_nonempty_line(bvh.out));
  for (const char* key : {"accel", "scene", "primitives", "rays", "query", "threads", "build_ms_median",
                          "trace_ms_median", "mrays_s_median", "hit_count", "memory_bytes", "scene_memory_bytes",
                          "input_memory_bytes", "out"}) {
    EXPECT_TRUE(summary.contains(key)) << key;
  }
  EXPECT_EQ(summary["precision"], "double");
  EXPECT_EQ(summary["accel"], "bvh:builder=sweep,leaf_size=2");
  EXPECT_EQ(summary["scene"], "far");
  EXPECT_EQ(summary["query"], "intersect");
  EXPECT_EQ(summary["rays"], rays.size());
  EXPECT_EQ(summary["primitives"], mesh.triangles.size());
  EXPECT_EQ(summary["hit_count"], found);

  // The PLY's doubles were kept: the same scene rounded to float (an ulp is 1 m at 1e7) gives other distances.
  const std::vector<HitD> rounded = brute_force_hits(to_double_mesh(to_float_mesh(mesh)), rays);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) differ += rounded[i].t != expected[i].t ? 1 : 0;
  EXPECT_GT(differ, found / 2);
}

TEST(CliTraceDouble, FloatPlyPlacedByOffsetAndOcclusion) {
  const auto dir = fresh_directory("offset");
  const TriangleMesh sphere = sphere_mesh();
  write_ply(dir / "sphere.ply", sphere, "float");
  const TriangleMeshD mesh = to_double_mesh(sphere, kOffset);
  const std::vector<RayD> rays = case_rays(mesh);
  write_rays_d(dir / "far.rays64", rays);
  const std::vector<HitD> expected = brute_force_hits(mesh, rays);

  const auto hits = run_cli({"trace", (dir / "sphere.ply").string(), (dir / "far.rays64").string(), "--precision",
                             "double", "--offset", kOffsetText, "--accel", "brute_force", "--repeat", "1", "--out",
                             (dir / "out.hits64").string()});
  ASSERT_EQ(hits.exit_code, 0) << hits.err;
  expect_same_hits(read_hits_d(dir / "out.hits64"), expected, true);
  const nlohmann::json summary = nlohmann::json::parse(last_nonempty_line(hits.out));
  EXPECT_EQ(summary["offset"], (nlohmann::json{kOffset.x, kOffset.y, kOffset.z}));

  const auto occ = run_cli({"trace", (dir / "sphere.ply").string(), (dir / "far.rays64").string(), "--precision",
                            "double", "--offset", kOffsetText, "--occlusion", "--repeat", "1", "--out",
                            (dir / "out.occ").string()});
  ASSERT_EQ(occ.exit_code, 0) << occ.err;
  const std::vector<std::uint8_t> occluded = read_occlusion(dir / "out.occ");
  ASSERT_EQ(occluded.size(), rays.size());
  std::size_t blocked = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    EXPECT_EQ(occluded[i] == 1, expected[i].found()) << "ray " << i;
    blocked += occluded[i];
  }
  EXPECT_EQ(nlohmann::json::parse(last_nonempty_line(occ.out))["query"], "occluded");
  EXPECT_EQ(nlohmann::json::parse(last_nonempty_line(occ.out))["hit_count"], blocked);
}

TEST(CliTraceDouble, UnsupportedOptionsAndBadInputsAreRefusedByName) {
  const auto dir = fresh_directory("errors");
  const TriangleMeshD mesh = to_double_mesh(sphere_mesh(), kOffset);
  write_ply(dir / "far.ply", mesh, "double");
  write_rays_d(dir / "far.rays64", case_rays(mesh));
  const std::string scene = (dir / "far.ply").string(), rays = (dir / "far.rays64").string();
  const auto expect_refused = [&](std::vector<std::string> extra, int code, const std::vector<std::string>& parts) {
    std::vector<std::string> args = {"trace", scene, rays, "--precision", "double", "--repeat", "1"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto result = run_cli(args);
    EXPECT_EQ(result.exit_code, code) << extra[0] << ": " << result.err;
    for (const std::string& part : parts) {
      EXPECT_NE(result.err.find(part), std::string::npos) << "'" << part << "' not in: " << result.err;
    }
  };
  expect_refused({"--accel", "kdtree"}, 2, {"'kdtree'", "no double-precision version"});
  expect_refused({"--accel", "bvh_wide"}, 2, {"'bvh_wide'", "no double-precision version"});
  expect_refused({"--accel", "bvh:bv=obb"}, 2, {"bv must be aabb", "'obb'"});
  expect_refused({"--accel", "bvh:leaf_size=0"}, 2, {"leaf_size"});
  expect_refused({"--packets"}, 2, {"--packets", "--precision double"});
  expect_refused({"--save", (dir / "s.bvh").string()}, 2, {"--save"});
  expect_refused({"--load", (dir / "s.bvh").string()}, 2, {"--load"});
  expect_refused({"--offset", "1,2"}, 2, {"--offset", "'1,2'"});
  expect_refused({"--offset", "1,nan,2"}, 2, {"--offset"});

  // A float .rays file is not a .rays64 file, even when its size is a multiple of 64 bytes (four rays), which was
  // read as two double rays of garbage; nor the other way round. The extension decides.
  write_rays(dir / "float.rays", std::vector<Ray>(4));
  const auto float_rays = run_cli({"trace", scene, (dir / "float.rays").string(), "--precision", "double"});
  EXPECT_EQ(float_rays.exit_code, 1);
  EXPECT_NE(float_rays.err.find("float.rays' is a .rays file by its name"), std::string::npos) << float_rays.err;
  const auto double_rays = run_cli({"trace", scene, rays});
  EXPECT_EQ(double_rays.exit_code, 1);
  EXPECT_NE(double_rays.err.find(".rays64' is a .rays64 file by its name"), std::string::npos) << double_rays.err;
  // Other names are read in the layout --precision says, their size checked.
  write_rays(dir / "float.bin", std::vector<Ray>(3));
  const auto other = run_cli({"trace", scene, (dir / "float.bin").string(), "--precision", "double"});
  EXPECT_EQ(other.exit_code, 1);
  EXPECT_NE(other.err.find("float.bin' has 96 bytes, not a multiple of the 64-byte record"), std::string::npos)
      << other.err;
  // A vertex outside the double domain is named.
  TriangleMeshD huge = mesh;
  huge.vertices[5].y = 1e300;
  write_ply(dir / "huge.ply", huge, "double");
  const auto domain = run_cli({"trace", (dir / "huge.ply").string(), rays, "--precision", "double"});
  EXPECT_EQ(domain.exit_code, 1);
  EXPECT_NE(domain.err.find("vertex 5"), std::string::npos) << domain.err;
  // --offset belongs to the double path; --precision takes float or double.
  const auto float_offset = run_cli({"trace", scene, rays, "--offset", "1,2,3"});
  EXPECT_EQ(float_offset.exit_code, 2);
  EXPECT_NE(float_offset.err.find("--precision double"), std::string::npos) << float_offset.err;
  const auto half = run_cli({"trace", scene, rays, "--precision", "half"});
  EXPECT_EQ(half.exit_code, 2);
  EXPECT_NE(half.err.find("half"), std::string::npos) << half.err;
}

}  // namespace
}  // namespace rayaccel
