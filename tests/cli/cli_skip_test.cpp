// End-to-end: `rayaccel trace --skip FILE` and `--mask FILE --geometry-mask M` (companion .ids files of a .rays file)
// give in-process brute force's answers with the same query context; bad companion files fail naming the file.
#include <gtest/gtest.h>

#include <cstring>
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

TEST(CliTraceSkip, BadCompanionFilesAreNamed) {
  const SmallCase c = make_small_case();
  write_ids(c.dir / "short.ids", std::vector<std::uint32_t>(3, 0));
  auto result = run_cli({"trace", c.ply.string(), c.rays.string(), "--skip", (c.dir / "short.ids").string()});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("short.ids"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("3 entries"), std::string::npos) << result.err;
  result = run_cli({"trace", c.ply.string(), c.rays.string(), "--skip", (c.dir / "short.ids").string(), "--packets"});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("--packets"), std::string::npos) << result.err;
}

}  // namespace
}  // namespace rayaccel
