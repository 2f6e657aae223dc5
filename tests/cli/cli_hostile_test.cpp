// End-to-end tests of the CLI on hostile input and output paths (issue #19): a device as the ray file, a PLY cut
// inside its header, output paths checked before any work, and a full device (/dev/full) reported as a failure
// instead of "wrote ...". Each run is bounded by timeout(1), so a hang fails the test instead of stalling CI.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_runner.h"
#include "../test_paths.h"

namespace rayaccel {
namespace {

using testing::CommandResult;
using testing::fresh_directory;
using testing::some_rays;

using testing::kSphereScene;

CommandResult run_bounded(std::vector<std::string> args) { return testing::run_cli_bounded(std::move(args)); }

TEST(CliHostile, DeviceAsRayFileIsRefusedNotReadForever) {
  if (!std::filesystem::exists("/dev/zero")) GTEST_SKIP() << "no /dev/zero";
  const auto result = run_bounded({"trace", kSphereScene, "/dev/zero", "--repeat", "1"});
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_NE(result.err.find("/dev/zero"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("not a regular file"), std::string::npos) << result.err;
}

TEST(CliHostile, PlyEndingInsideItsHeaderIsAnErrorNotAHang) {
  const auto dir = fresh_directory("cut");
  const auto ply = dir / "cut.ply";
  std::ofstream(ply, std::ios::binary) << "ply\nformat ascii 1.0\n";
  const auto result = run_bounded({"info", ply.string()});
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_NE(result.err.find("cut.ply"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("ends inside its header"), std::string::npos) << result.err;
}

TEST(CliHostile, OutputPathsAreCheckedBeforeAnyWork) {
  const auto dir = fresh_directory("paths");
  const auto missing = dir / "no_such_dir";
  const auto rays = some_rays(dir);
  const auto trace =
      run_bounded({"trace", kSphereScene, rays.string(), "--repeat", "1", "--out", (missing / "x.hits").string()});
  EXPECT_EQ(trace.exit_code, 1) << trace.err;
  EXPECT_NE(trace.err.find("does not exist"), std::string::npos) << trace.err;
  EXPECT_EQ(trace.out.find("build_ms"), std::string::npos) << "no work before the check: " << trace.out;
  const auto render = run_bounded({"render", kSphereScene, "--res", "8x8", "--out", (missing / "x.png").string()});
  EXPECT_EQ(render.exit_code, 1) << render.err;
  EXPECT_NE(render.err.find("x.png"), std::string::npos) << render.err;
  const auto bench = run_bounded({"bench", kSphereScene, "--accel", "bvh", "--res", "8", "--repeat", "1", "--json",
                                  (missing / "x.json").string()});
  EXPECT_EQ(bench.exit_code, 1) << bench.err;
  EXPECT_NE(bench.err.find("x.json"), std::string::npos) << bench.err;
  EXPECT_EQ(bench.out.find("bvh "), std::string::npos) << "no table before the check: " << bench.out;
  for (const char* option : {"--json", "--spp-map"}) {  // whitted's extra outputs, checked before rendering
    const auto whitted = run_bounded({"render", kSphereScene, "--mode", "whitted", "--res", "8x8", "--out",
                                      (dir / "w.png").string(), option, (missing / "x.out").string()});
    EXPECT_EQ(whitted.exit_code, 1) << option << ": " << whitted.err;
    EXPECT_NE(whitted.err.find("x.out"), std::string::npos) << whitted.err;
    EXPECT_EQ(whitted.out.find("wrote"), std::string::npos) << "no render before the check: " << whitted.out;
  }
  const auto images = run_bounded({"bench", kSphereScene, "--accel", "bvh", "--res", "8", "--repeat", "1", "--images",
                                   rays.string()});
  EXPECT_EQ(images.exit_code, 1) << images.err;
  EXPECT_NE(images.err.find("not a directory"), std::string::npos) << images.err;
  EXPECT_FALSE(std::filesystem::exists(missing));
}

TEST(CliHostile, FullDeviceIsAFailureNotWrote) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const auto dir = fresh_directory("full");
  const auto rays = some_rays(dir);
  const auto render = run_bounded({"render", kSphereScene, "--res", "8x8", "--out", "/dev/full"});
  EXPECT_EQ(render.exit_code, 1) << render.err;
  EXPECT_EQ(render.out.find("wrote"), std::string::npos) << render.out;
  EXPECT_NE(render.err.find("No space left on device"), std::string::npos) << render.err;
  const auto trace = run_bounded({"trace", kSphereScene, rays.string(), "--repeat", "1", "--out", "/dev/full"});
  EXPECT_EQ(trace.exit_code, 1) << trace.err;
  EXPECT_NE(trace.err.find("No space left on device"), std::string::npos) << trace.err;
  const auto bench =
      run_bounded({"bench", kSphereScene, "--accel", "bvh", "--res", "8", "--repeat", "1", "--json", "/dev/full"});
  EXPECT_EQ(bench.exit_code, 1) << bench.err;
  EXPECT_NE(bench.err.find("No space left on device"), std::string::npos) << bench.err;
}

}  // namespace
}  // namespace rayaccel
