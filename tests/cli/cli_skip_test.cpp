// End-to-end: `rayaccel trace --skip FILE` and `--mask FILE --geometry-mask M` (companion .ids files of a .rays file)
// give in-process brute force's answers with the same query context; bad companion files fail naming the file. On a
// file of several meshes, --geometry-ids names each hit's mesh, --geometry-mask / --skip-geometry act per mesh and
// --enabled hides primitives.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "small_case.h"
#include "rayaccel/accel/brute_force.h"
#include "rayaccel/scene/import.h"
#include "rayaccel/scene/ray_io.h"

namespace rayaccel {
namespace {

using testing::make_small_case;
using testing::run_cli;
using testing::SmallCase;

TEST(CliTraceSkip, SkipFileGivesTheNextHit) {
  const SmallCase c = make_small_case();
  const Scene scene = load_scene(c.ply.string());
  const std::vector<Ray> rays = read_rays(c.rays);
  BruteForce oracle;
  oracle.build(scene);
  std::vector<Hit> first(rays.size());
  oracle.intersect(rays, first);
  std::vector<std::uint32_t> skip(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) skip[i] = first[i].prim_id;
  write_ids(c.dir / "first.ids", skip);

  QueryContext context;
  context.skip_primitive = skip;
  std::vector<Hit> expected(rays.size());
  oracle.intersect(context, rays, expected);
  const auto out = c.dir / "second.hits";
  const auto result = run_cli({"trace", c.ply.string(), c.rays.string(), "--accel", "bvh_wide", "--repeat", "1",
                               "--skip", (c.dir / "first.ids").string(), "--out", out.string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::vector<Hit> got = read_hits(out);
  ASSERT_EQ(got.size(), rays.size());
  int changed = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(std::memcmp(&got[i], &expected[i], sizeof(Hit)), 0) << "ray " << i;
    changed += got[i].prim_id != first[i].prim_id;
  }
  EXPECT_GT(changed, 0) << "skipping the first hit must change answers";
  // Through the packet form: the same answers (t bit for bit; the primitive may differ only at a tie in t).
  const auto packets_out = c.dir / "second_packets.hits";
  ASSERT_EQ(run_cli({"trace", c.ply.string(), c.rays.string(), "--accel", "bvh_wide", "--repeat", "1", "--packets",
                     "--skip", (c.dir / "first.ids").string(), "--out", packets_out.string()})
                .exit_code,
            0);
  const std::vector<Hit> in_packets = read_hits(packets_out);
  ASSERT_EQ(in_packets.size(), rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) EXPECT_EQ(in_packets[i].t, expected[i].t) << "ray " << i;

  // A ray mask of 1 against a geometry mask of 2 hides the scene; against 3 it does not.
  write_ids(c.dir / "ones.ids", std::vector<std::uint32_t>(rays.size(), 1));
  const auto occ = c.dir / "masked.occ";
  ASSERT_EQ(run_cli({"trace", c.ply.string(), c.rays.string(), "--occlusion", "--repeat", "1", "--mask",
                     (c.dir / "ones.ids").string(), "--geometry-mask", "2", "--out", occ.string()})
                .exit_code,
            0);
  for (std::uint8_t o : read_occlusion(occ)) EXPECT_EQ(o, 0);
  ASSERT_EQ(run_cli({"trace", c.ply.string(), c.rays.string(), "--occlusion", "--repeat", "1", "--mask",
                     (c.dir / "ones.ids").string(), "--geometry-mask", "3", "--out", occ.string()})
                .exit_code,
            0);
  const std::vector<std::uint8_t> seen = read_occlusion(occ);
  for (std::size_t i = 0; i < rays.size(); ++i) EXPECT_EQ(seen[i], first[i].found() ? 1 : 0) << "ray " << i;
}

TEST(CliTraceSkip, GeometryIdsAndMasksOfASceneFileOfSeveralMeshes) {
  // Two OBJ objects: a floor (two triangles at z = 0 over [0, 4]^2) and a lamp above part of it (one triangle at
  // z = 1); rays straight down on a grid, some over the lamp.
  const SmallCase c = make_small_case();
  const auto obj = c.dir / "room.obj";
  std::ofstream(obj) << "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 0 4 0\nv 0.5 0.5 1\nv 3 0.5 1\nv 0.5 3 1\n"
                        "o floor\nf 1 2 3\nf 1 3 4\no lamp\nf 5 6 7\n";
  std::vector<Ray> rays;
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) {  // off the floor's diagonal and the lamp's edges: no ties between triangles
      rays.push_back(Ray{Vec3{0.25f + 0.5f * i, 0.3f + 0.5f * j, 5.0f}, 0.0f, Vec3{0, 0, -1}});
    }
  }
  const auto rays_file = c.dir / "down.rays";
  write_rays(rays_file, rays);
  GeometryTable geometries;
  const Scene scene = load_scene(obj.string(), &geometries);
  ASSERT_EQ(geometries.geometry_count(), 2u);
  BruteForce oracle;
  oracle.build(scene);

  // Without a context: each hit's mesh, in a companion of the .hits file.
  const auto hits_file = c.dir / "down.hits", ids_file = c.dir / "down.ids";
  auto result = run_cli({"trace", obj.string(), rays_file.string(), "--repeat", "1", "--out", hits_file.string(),
                         "--geometry-ids", ids_file.string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::vector<Hit> expected(rays.size());
  oracle.intersect(rays, expected);
  std::vector<std::uint32_t> expected_ids(rays.size());
  geometries.geometry_ids(expected, expected_ids);
  EXPECT_EQ(read_ids(ids_file), expected_ids);
  int per_geometry[2] = {0, 0};
  for (std::uint32_t g : expected_ids) per_geometry[g] += 1;  // every ray hits: a miss would index out of range
  EXPECT_GT(per_geometry[0], 0);
  EXPECT_GT(per_geometry[1], 0);

  // Masks per mesh: rays of mask 1 against the masks "1,2" see the floor only; skipping geometry 0 shows the lamp.
  const auto check = [&](const std::vector<std::string>& options, const QueryContext& context) {
    std::vector<std::string> argv = {"trace", obj.string(), rays_file.string(), "--repeat", "1", "--out",
                                     hits_file.string(), "--geometry-ids", ids_file.string()};
    argv.insert(argv.end(), options.begin(), options.end());
    const auto run = run_cli(argv);
    ASSERT_EQ(run.exit_code, 0) << run.err;
    std::vector<Hit> want(rays.size());
    oracle.intersect(context, rays, want);
    const std::vector<Hit> got = read_hits(hits_file);
    ASSERT_EQ(got.size(), rays.size());
    for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(std::memcmp(&got[i], &want[i], sizeof(Hit)), 0) << i;
    std::vector<std::uint32_t> want_ids(rays.size());
    geometries.geometry_ids(want, want_ids);
    EXPECT_EQ(read_ids(ids_file), want_ids);
  };
  write_ids(c.dir / "ones.ids", std::vector<std::uint32_t>(rays.size(), 1));
  const std::uint32_t masks[2] = {1, 2};
  const std::vector<std::uint32_t> ones(rays.size(), 1), zeros(rays.size(), 0);
  QueryContext floor_only;
  floor_only.ray_mask = ones;
  floor_only.geometry_mask = masks;
  floor_only.geometry_starts = geometries.starts();
  check({"--mask", (c.dir / "ones.ids").string(), "--geometry-mask", "1,0x2"}, floor_only);
  write_ids(c.dir / "zeros.ids", zeros);
  QueryContext lamp_only;
  lamp_only.skip_geometry = zeros;
  lamp_only.geometry_starts = geometries.starts();
  check({"--skip-geometry", (c.dir / "zeros.ids").string()}, lamp_only);
  // Primitive switches: the lamp and the floor's first triangle hidden.
  const std::vector<std::uint32_t> switches = {0, 7, 0};
  write_ids(c.dir / "switches.ids", switches);
  const std::vector<std::uint8_t> enabled = {0, 1, 0};
  QueryContext switched;
  switched.primitive_enabled = enabled;
  check({"--enabled", (c.dir / "switches.ids").string()}, switched);

  // A mask list of the wrong length, a bad mask and --geometry-ids without --out fail naming what is wrong.
  result = run_cli({"trace", obj.string(), rays_file.string(), "--geometry-mask", "1,2,3"});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("3 masks for a scene of 2 geometries"), std::string::npos) << result.err;
  result = run_cli({"trace", obj.string(), rays_file.string(), "--geometry-mask", "1,lamp"});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("'lamp'"), std::string::npos) << result.err;
  result = run_cli({"trace", obj.string(), rays_file.string(), "--enabled", (c.dir / "zeros.ids").string()});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("64 entries for 3 primitives"), std::string::npos) << result.err;
  result = run_cli({"trace", obj.string(), rays_file.string(), "--geometry-ids", ids_file.string()});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("needs --out"), std::string::npos) << result.err;
}

TEST(CliTraceSkip, BadCompanionFilesAreNamed) {
  const SmallCase c = make_small_case();
  write_ids(c.dir / "short.ids", std::vector<std::uint32_t>(3, 0));
  auto result = run_cli({"trace", c.ply.string(), c.rays.string(), "--skip", (c.dir / "short.ids").string()});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("short.ids"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("3 entries"), std::string::npos) << result.err;
  result = run_cli({"trace", c.ply.string(), c.rays.string(), "--skip", (c.dir / "short.ids").string(), "--instances"});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("--instances"), std::string::npos) << result.err;
}

}  // namespace
}  // namespace rayaccel
