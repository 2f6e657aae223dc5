// `render --beams` and `render --cones` end to end: beams write the very image single rays write, cone effects by
// cones match their many-ray estimate (counts and error), bad values and unsupported structures are refused first.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "rayaccel/render/image.h"
#include "rayaccel/render/image_compare.h"

namespace rayaccel {
namespace {

using testing::fresh_directory;
using testing::run_cli;

const std::vector<std::string> kSierpinskiArgs = {"builtin:sierpinski", "--res", "48x40"};

std::vector<std::string> render_args(std::vector<std::string> extra) {
  std::vector<std::string> args = {"render"};
  args.insert(args.end(), kSierpinskiArgs.begin(), kSierpinskiArgs.end());
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

/// The number printed after `label` in `out` (NaN when absent).
double number_after(const std::string& out, const std::string& label) {
  const std::size_t at = out.find(label);
  return at == std::string::npos ? std::nan("") : std::strtod(out.c_str() + at + label.size(), nullptr);
}

/// The count printed before `label` ("2144 rays traced": 2144), NaN when absent.
double count_before(const std::string& out, const std::string& label) {
  const std::size_t at = out.find(label);
  if (at == std::string::npos) return std::nan("");
  std::size_t begin = out.rfind(' ', at - 2);
  begin = begin == std::string::npos ? 0 : begin + 1;
  return std::strtod(out.c_str() + begin, nullptr);
}

TEST(CliGeneralized, ConeEffectsRunByConesAndByRays) {
  const auto dir = fresh_directory("cones");
  const int pixels = 48 * 40;
  std::map<std::string, Image> references;
  for (const char* effect : {"shadows", "aa"}) {
    const auto ref = dir / (std::string("ref_") + effect + ".png");
    auto a = run_cli(render_args({"--cones", effect, "--cone-rays", "16", "--out", ref.string()}));
    ASSERT_EQ(a.exit_code, 0) << a.err;
    references[effect] = load_png(ref);
  }
  for (const char* effect : {"shadows", "aa"}) {
    const auto ref = dir / (std::string("ref_") + effect + ".png"), cone = dir / "cone.png";
    auto a = run_cli(render_args({"--cones", effect, "--cone-rays", "16", "--out", (dir / "rays.png").string()}));
    ASSERT_EQ(a.exit_code, 0) << a.err;
    auto b = run_cli(render_args({"--cones", effect, "--cone-coverage", "pattern", "--cone-samples", "16",
                                  "--reference", ref.string(), "--out", cone.string()}));
    ASSERT_EQ(b.exit_code, 0) << b.err;
    // One cone per shading point where the estimate traces 16 rays: anti-aliasing shades every pixel once; shadows
    // one point per pixel that hits the scene.
    const double rays = count_before(a.out, "rays traced"), cones = count_before(b.out, "cones queried");
    if (std::string(effect) == "aa") {
      EXPECT_EQ(cones, pixels) << b.out;
    }
    EXPECT_GT(cones, 0.0) << b.out;
    EXPECT_LE(cones, pixels) << b.out;
    EXPECT_EQ(rays, 16.0 * cones) << a.out << b.out;
    // The printed error is the image's against the reference, small (both estimate the same integral: 1.6 and 5.8
    // of 255 when written), and far below its error against the other effect's reference (about 30).
    const Image image = load_png(cone);
    const double rmse = compare_images(image, references[effect]).rmse;
    EXPECT_NEAR(number_after(b.out, "RMSE "), rmse, 0.0005) << b.out;
    EXPECT_LT(rmse, 12.0) << effect;
    const char* other = std::string(effect) == "aa" ? "shadows" : "aa";
    EXPECT_LT(2.0 * rmse, compare_images(image, references[other]).rmse) << effect;
    EXPECT_NE(b.out.find("16 pattern directions"), std::string::npos) << b.out;
    // The default, analytic coverage: the same checks against the same reference.
    const auto analytic = dir / "analytic.png";
    auto c = run_cli(render_args({"--cones", effect, "--reference", ref.string(), "--out", analytic.string()}));
    ASSERT_EQ(c.exit_code, 0) << c.err;
    EXPECT_NE(c.out.find("analytic coverage"), std::string::npos) << c.out;
    const Image analytic_image = load_png(analytic);
    const double analytic_rmse = compare_images(analytic_image, references[effect]).rmse;
    EXPECT_NEAR(number_after(c.out, "RMSE "), analytic_rmse, 0.0005) << c.out;
    EXPECT_LT(analytic_rmse, 12.0) << effect;
    EXPECT_LT(2.0 * analytic_rmse, compare_images(analytic_image, references[other]).rmse) << effect;
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
