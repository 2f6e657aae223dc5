// `render --beams` and `render --cones` end to end: beams write the very image single rays write, cone effects run by
// cones and by rays, and bad values or structures without generalized rays are refused before any work.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "rayaccel/render/image.h"
#include "rayaccel/render/image_compare.h"

namespace rayaccel {
namespace {

using testing::fresh_directory;
using testing::run_cli;

const std::vector<std::string> kScene = {"builtin:sierpinski", "--res", "48x40"};

std::vector<std::string> render_args(std::vector<std::string> extra) {
  std::vector<std::string> args = {"render"};
  args.insert(args.end(), kScene.begin(), kScene.end());
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

TEST(CliGeneralized, BeamsWriteTheImageOfSingleRays) {
  const auto dir = fresh_directory("beams");
  for (const char* spec : {"bvh", "bvh_wide"}) {
    const auto rays = dir / "rays.png", beams = dir / "beams.png";
    auto a = run_cli(render_args({"--accel", spec, "--out", rays.string()}));
    ASSERT_EQ(a.exit_code, 0) << a.err;
    auto b = run_cli(render_args({"--accel", spec, "--beams", "--beam-tile", "8", "--out", beams.string()}));
    ASSERT_EQ(b.exit_code, 0) << b.err;
    EXPECT_NE(b.out.find("beams:"), std::string::npos) << b.out;
    EXPECT_EQ(compare_images(load_png(rays), load_png(beams)).rmse, 0.0) << spec;
  }
}

TEST(CliGeneralized, ConeEffectsRunByConesAndByRays) {
  const auto dir = fresh_directory("cones");
  for (const char* effect : {"shadows", "aa"}) {
    const auto ref = dir / "ref.png", cone = dir / "cone.png";
    auto a = run_cli(render_args({"--cones", effect, "--cone-rays", "16", "--out", ref.string()}));
    ASSERT_EQ(a.exit_code, 0) << a.err;
    EXPECT_NE(a.out.find("rays traced"), std::string::npos) << a.out;
    auto b = run_cli(render_args({"--cones", effect, "--cone-coverage", "pattern", "--cone-samples", "16",
                                  "--reference", ref.string(), "--out", cone.string()}));
    ASSERT_EQ(b.exit_code, 0) << b.err;
    EXPECT_NE(b.out.find("cones queried"), std::string::npos) << b.out;
    EXPECT_NE(b.out.find("16 pattern directions"), std::string::npos) << b.out;
    EXPECT_NE(b.out.find("RMSE"), std::string::npos) << b.out;
    auto c = run_cli(render_args({"--cones", effect, "--reference", ref.string(), "--out", cone.string()}));
    ASSERT_EQ(c.exit_code, 0) << c.err;
    EXPECT_NE(c.out.find("analytic coverage"), std::string::npos) << c.out;
  }
}

TEST(CliGeneralized, BadValuesAreRefusedNamingTheOption) {
  const auto dir = fresh_directory("generalized_bad");
  const std::string out = (dir / "x.png").string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--cones", "fog"}, "--cones"},
      {{"--cones", "aa", "--cone-samples", "0"}, "--cone-samples"},
      {{"--cones", "aa", "--cone-coverage", "exact"}, "--cone-coverage"},
      {{"--cones", "shadows", "--cone-light-radius", "0"}, "--cone-light-radius"},
      {{"--cones", "aa", "--beams"}, "--cones"},
      {{"--beams", "--beam-tile", "0"}, "--beam-tile"},
      {{"--beams", "--mode", "heatmap"}, "--beams"},
      {{"--beams", "--accel", "octree"}, "octree"},
      {{"--cones", "aa", "--accel", "grid"}, "grid"},
  };
  for (const auto& [extra, needle] : cases) {
    std::vector<std::string> args = extra;
    args.insert(args.end(), {"--out", out});
    const auto result = run_cli(render_args(args));
    EXPECT_NE(result.exit_code, 0) << needle;
    EXPECT_NE(result.err.find(needle), std::string::npos) << needle << ": " << result.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << needle;
  }
}

}  // namespace
}  // namespace rayaccel
