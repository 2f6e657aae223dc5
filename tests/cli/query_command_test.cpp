// End-to-end tests of `rayaccel query`: its answer files equal the library's in-process answers (brute force), and
// a bad mode, structure or flag fails with exit code 2 and a message naming it.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/scene/builtin_scenes.h"
#include "rayaccel/scene/ray_io.h"

namespace rayaccel {
namespace {

using testing::fresh_directory;
using testing::run_cli;

constexpr const char* kScene = "builtin:sphere:level=2";

std::vector<Vec3> grid_points() {
  std::vector<Vec3> points;
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < 9; ++j) points.push_back({-1.6f + 0.4f * float(i), -1.6f + 0.4f * float(j), 0.1f * float(i - j)});
  }
  return points;
}

TEST(CliQuery, AnswerFilesEqualTheLibrarys) {
  const auto dir = fresh_directory("cli_query");
  const Scene scene = make_builtin_scene("sphere", {{"level", "2"}});
  auto brute = make_accelerator("brute_force");
  brute->build(scene);

  const std::vector<Vec3> points = grid_points();
  write_points(dir / "p.points", points);
  std::vector<Ray> rays;
  for (const Vec3& p : points) rays.push_back(Ray{p * 2.0f, 0.0f, Vec3{0.3f, -0.2f, 0.1f} - p, 100.0f});
  write_rays(dir / "r.rays", rays);

  auto result = run_cli({"query", "closest", kScene, (dir / "p.points").string(), "--accel", "bvh",
                         "--repeat", "1", "--out", (dir / "out.closest").string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::vector<ClosestPoint> expected(points.size());
  brute->closest_points(points, expected);
  const std::vector<ClosestPoint> got = read_closest_points(dir / "out.closest");
  ASSERT_EQ(got.size(), points.size());
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i].distance, expected[i].distance) << i;

  result = run_cli({"query", "all-hits", kScene, (dir / "r.rays").string(), "--accel", "bvh_wide", "--repeat", "1",
                    "--out", (dir / "out.hits").string(), "--counts", (dir / "out.counts").string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::vector<Hit> expected_hits, one;
  for (const Ray& ray : rays) {
    brute->all_hits(ray, one);
    expected_hits.insert(expected_hits.end(), one.begin(), one.end());
  }
  const std::vector<Hit> got_hits = read_hits(dir / "out.hits");
  ASSERT_EQ(got_hits.size(), expected_hits.size());
  EXPECT_GT(got_hits.size(), rays.size());
  EXPECT_EQ(std::memcmp(got_hits.data(), expected_hits.data(), got_hits.size() * sizeof(Hit)), 0);
  EXPECT_EQ(testing::read_file(dir / "out.counts").size(), rays.size() * 4);
}

TEST(CliQuery, BadModesStructuresAndFlagsAreUsageErrors) {
  const auto dir = fresh_directory("cli_query_bad");
  write_points(dir / "p.points", grid_points());
  const std::string points = (dir / "p.points").string();
  auto result = run_cli({"query", "nearest", kScene, points});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("unknown query 'nearest'"), std::string::npos) << result.err;
  result = run_cli({"query", "closest", kScene, points, "--accel", "kdtree"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("kdtree"), std::string::npos) << result.err;
  result = run_cli({"query", "inside", kScene, points, "--parity-rays", "4"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--parity-rays"), std::string::npos) << result.err;
  result = run_cli({"query", "closest", kScene, points, "--counts", (dir / "c").string()});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--counts"), std::string::npos) << result.err;
  result = run_cli({"query", "inside", kScene, points, "--max-distance", "2"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--max-distance applies to the closest query only"), std::string::npos) << result.err;
  result = run_cli({"query", "closest", kScene, (dir / "missing.points").string()});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("missing.points"), std::string::npos) << result.err;
}

}  // namespace
}  // namespace rayaccel
