// End-to-end tests of the rayaccel command-line tool, run as a separate process: trace output equals in-process
// brute force, list/info print what the library says, and bad arguments fail with a message naming the value.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "small_case.h"
#include "rayaccel/accel/brute_force.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/render/image_compare.h"
#include "rayaccel/scene/import.h"
#include "rayaccel/scene/ray_io.h"
#include "rayaccel/version.h"

namespace rayaccel {
namespace {

using testing::fresh_directory;
using testing::last_nonempty_line;
using testing::make_small_case;
using testing::run_cli;
using testing::SmallCase;

/// Brute force's closest hits of the case's rays, read back from its files.
std::vector<Hit> brute_force_hits(const SmallCase& c) {
  const Scene scene = load_scene(c.ply.string());
  BruteForce oracle;
  oracle.build(scene);
  const std::vector<Ray> rays = read_rays(c.rays);
  std::vector<Hit> hits(rays.size());
  oracle.intersect(rays, hits);
  return hits;
}

TEST(CliTrace, HitsFileEqualsInProcessBruteForce) {
  const SmallCase c = make_small_case();
  const auto out = c.dir / "out.hits";
  const auto result = run_cli({"trace", c.ply.string(), c.rays.string(), "--accel", "brute_force", "--repeat", "2",
                               "--out", out.string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;

  const Scene scene = load_scene(c.ply.string());
  const std::vector<Ray> rays = read_rays(c.rays);
  const std::vector<Hit> expected = brute_force_hits(c);
  const std::vector<Hit> got = read_hits(out);
  ASSERT_EQ(got.size(), expected.size());
  std::size_t found = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(std::memcmp(&got[i], &expected[i], sizeof(Hit)), 0)
        << "ray " << i << ": got t=" << got[i].t << " prim=" << got[i].prim_id << ", expected t=" << expected[i].t
        << " prim=" << expected[i].prim_id;
    found += expected[i].found() ? 1 : 0;
  }
  EXPECT_GT(found, rays.size() / 3) << "the rays should mostly hit";
  EXPECT_LT(found, rays.size()) << "some rays should miss";

  const nlohmann::json summary = nlohmann::json::parse(last_nonempty_line(result.out));
  for (const char* key : {"accel", "scene", "primitives", "rays", "threads", "build_ms_median", "trace_ms_median",
                          "mrays_s_median", "hit_count", "memory_bytes", "scene_memory_bytes"}) {
    EXPECT_TRUE(summary.contains(key)) << key;
  }
  EXPECT_EQ(summary["accel"], "brute_force");
  EXPECT_EQ(summary["rays"], rays.size());
  EXPECT_EQ(summary["primitives"], scene.primitive_count());
  EXPECT_EQ(summary["hit_count"], found);
  EXPECT_EQ(summary["scene_memory_bytes"], scene.memory_bytes()) << "the scene's arrays, apart from the structure's";
}

TEST(CliTrace, PacketsGiveTheClosestHits) {
  const SmallCase c = make_small_case();
  const auto out = c.dir / "packets.hits";
  const auto result = run_cli({"trace", c.ply.string(), c.rays.string(), "--accel", "bvh_wide", "--packets",
                               "--repeat", "1", "--out", out.string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::vector<Hit> expected = brute_force_hits(c);
  const std::vector<Hit> got = read_hits(out);
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    // The same kernel on the same ray: the same t bit for bit; another primitive only in a tie at that t.
    EXPECT_EQ(std::memcmp(&got[i].t, &expected[i].t, sizeof(float)), 0) << "ray " << i;
    EXPECT_EQ(got[i].found(), expected[i].found()) << "ray " << i;
  }
  EXPECT_EQ(nlohmann::json::parse(last_nonempty_line(result.out))["query"], "intersect_packets");
}

TEST(CliTrace, SaveThenLoadGivesTheSameHits) {
  const SmallCase c = make_small_case();
  for (const std::string accel : {"bvh_wide", "bvh:bv=obb,builder=sbvh"}) {
    const auto saved = c.dir / "saved.structure";
    const auto built_hits = c.dir / "built.hits", loaded_hits = c.dir / "loaded.hits";
    const auto built = run_cli({"trace", c.ply.string(), c.rays.string(), "--accel", accel, "--repeat", "1",
                                "--save", saved.string(), "--out", built_hits.string()});
    ASSERT_EQ(built.exit_code, 0) << built.err;
    EXPECT_EQ(nlohmann::json::parse(last_nonempty_line(built.out))["saved_to"], saved.string());
    const auto loaded = run_cli({"trace", c.ply.string(), c.rays.string(), "--repeat", "1", "--load", saved.string(),
                                 "--out", loaded_hits.string()});
    ASSERT_EQ(loaded.exit_code, 0) << loaded.err;
    const nlohmann::json summary = nlohmann::json::parse(last_nonempty_line(loaded.out));
    EXPECT_TRUE(summary.contains("load_ms"));
    EXPECT_FALSE(summary.contains("build_ms_median"));
    EXPECT_EQ(testing::read_file(built_hits), testing::read_file(loaded_hits)) << accel;
  }
  const auto kd = run_cli({"trace", c.ply.string(), c.rays.string(), "--accel", "kdtree", "--save",
                           (c.dir / "kd.structure").string()});
  EXPECT_EQ(kd.exit_code, 2);
  EXPECT_NE(kd.err.find("cannot be saved"), std::string::npos) << kd.err;
  const auto both = run_cli({"trace", c.ply.string(), c.rays.string(), "--accel", "bvh_wide", "--load",
                             (c.dir / "saved.structure").string()});
  EXPECT_EQ(both.exit_code, 2);
  const auto foreign = run_cli({"trace", c.ply.string(), c.rays.string(), "--load", c.rays.string()});
  EXPECT_EQ(foreign.exit_code, 1);
  EXPECT_NE(foreign.err.find(c.rays.string()), std::string::npos) << foreign.err;
}

/// Brute force's any-hit answers for the small case's rays (the reference of the --occlusion tests).
std::vector<std::uint8_t> brute_force_occlusion(const SmallCase& c) {
  const Scene scene = load_scene(c.ply.string());
  BruteForce oracle;
  oracle.build(scene);
  const std::vector<Ray> rays = read_rays(c.rays);
  std::vector<std::uint8_t> expected(rays.size());
  oracle.occluded(rays, expected);
  return expected;
}

TEST(CliTrace, OcclusionWritesOccFile) {
  const SmallCase c = make_small_case();
  const auto out = c.dir / "out.occ";
  const auto result = run_cli({"trace", c.ply.string(), c.rays.string(), "--accel", "brute_force", "--occlusion",
                               "--threads", "1", "--repeat", "1", "--out", out.string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::vector<std::uint8_t> expected = brute_force_occlusion(c);
  EXPECT_EQ(read_occlusion(out), expected);
  const nlohmann::json summary = nlohmann::json::parse(last_nonempty_line(result.out));
  EXPECT_EQ(summary["threads"], 1);
  EXPECT_EQ(summary["hit_count"], std::count(expected.begin(), expected.end(), std::uint8_t{1}));
}

TEST(CliTrace, OcclusionPacketsGiveWhatBruteForceDecides) {
  const SmallCase c = make_small_case();
  const auto out = c.dir / "packets.occ";
  const auto result = run_cli({"trace", c.ply.string(), c.rays.string(), "--accel", "bvh_wide", "--occlusion",
                               "--packets", "--repeat", "1", "--out", out.string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::vector<std::uint8_t> expected = brute_force_occlusion(c);
  EXPECT_EQ(read_occlusion(out), expected);
  EXPECT_EQ(nlohmann::json::parse(last_nonempty_line(result.out))["query"], "occluded_packets");
}

TEST(Cli, VersionPrintsTheVersionHeader) {
  const auto result = run_cli({"--version"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out, std::string("rayaccel ") + RAYACCEL_VERSION_STRING + "\n");
  EXPECT_EQ(RAYACCEL_VERSION_STRING, std::to_string(RAYACCEL_VERSION_MAJOR) + "." +
                                         std::to_string(RAYACCEL_VERSION_MINOR) + "." +
                                         std::to_string(RAYACCEL_VERSION_PATCH));
}

TEST(CliList, NamesPrintsExactlyTheVariantNames) {
  const auto result = run_cli({"list", "--names"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::string expected;
  for (const auto& name : accelerator_variant_names()) expected += name + "\n";
  EXPECT_EQ(result.out, expected);
}

TEST(CliList, DescribesEveryStructure) {
  const auto result = run_cli({"list"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  for (const auto& info : accelerator_registry()) {
    EXPECT_NE(result.out.find(info.name), std::string::npos) << info.name;
    EXPECT_NE(result.out.find(info.description), std::string::npos) << info.name;
    for (const auto& option : info.options) EXPECT_NE(result.out.find(option.key), std::string::npos) << option.key;
  }
}

TEST(CliInfo, PrintsCounts) {
  const SmallCase c = make_small_case();
  const auto result = run_cli({"info", c.ply.string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("primitives:  302\n"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("degenerate:  1\n"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("invalid:     0\n"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("load time:"), std::string::npos) << result.out;
}

/// Each bad invocation must exit with `code` and name `value` in its one-line error.
struct BadCase {
  std::vector<std::string> args;
  std::string value;
  int code;
};

TEST(CliErrors, BadArgumentsNameTheValue) {
  const SmallCase c = make_small_case();
  const std::string ply = c.ply.string(), rays = c.rays.string();
  const std::vector<BadCase> cases = {
      {{"trace", ply, rays, "--accel", "no_such_structure"}, "no_such_structure", 2},
      {{"trace", ply, rays, "--accel", "brute_force:bogus_key=1"}, "bogus_key", 2},
      {{"trace", ply, rays, "--threads", "0"}, "--threads", 2},
      {{"trace", ply, rays, "--threads", "many"}, "many", 2},
      {{"trace", ply, rays, "--repeat", "0"}, "--repeat", 2},
      {{"trace", ply, rays, "--no-such-option"}, "--no-such-option", 2},
      {{"trace", (c.dir / "missing.ply").string(), rays}, "missing.ply", 2},
      {{"trace", ply, (c.dir / "missing.rays").string()}, "missing.rays", 1},
      {{"info", (c.dir / "missing.ply").string()}, "missing.ply", 2},
      {{"render", ply, "--eye", "1,2"}, "1,2", 2},
      {{"render", ply, "--at", "1,x,3"}, "1,x,3", 2},
      {{"render", ply, "--res", "0x10"}, "0x10", 2},
      {{"render", ply, "--mode", "sepia"}, "sepia", 2},
      {{"render", ply, "--fov", "200"}, "200", 2},
      {{"bench", ply, "--res", "0"}, "--res", 2},
      {{"bench", ply, "--rays", "primary,cosmic"}, "cosmic", 2},
      {{"bench", ply, "--accel", "brute_force,nope"}, "nope", 2},
      {{"bench", ply, "--compare", "optix"}, "optix", 2},
      {{"bench", ply, "--heat-max", "0"}, "--heat-max", 2},
      {{"render", ply, "--heat-max", "0"}, "--heat-max", 2},
      {{"render", ply, "--mode", "whitted", "--aa", "uniform:n=3"}, "n=3", 2},
      {{"render", ply, "--mode", "whitted", "--shadows", "some"}, "some", 2},
      {{"render", ply, "--mode", "whitted", "--max-depth", "99"}, "99", 2},
      {{"render", ply, "--mode", "whitted", "--mirror", "2"}, "--mirror", 2},
      {{"render", ply, "--mode", "whitted", "--reference", (c.dir / "none.png").string()}, "none.png", 1},
      {{"frobnicate"}, "frobnicate", 2},
  };
  for (const auto& bad : cases) {
    std::string joined;
    for (const auto& a : bad.args) joined += a + " ";
    const auto result = run_cli(bad.args);
    EXPECT_EQ(result.exit_code, bad.code) << joined << "\nstderr: " << result.err;
    EXPECT_NE(result.err.find(bad.value), std::string::npos) << joined << "\nstderr: " << result.err;
    EXPECT_NE(result.err.find("error"), std::string::npos) << joined << "\nstderr: " << result.err;
  }
}

TEST(CliTrace, CorruptRaysFileIsARuntimeError) {
  const SmallCase c = make_small_case();
  const auto bad = c.dir / "bad.rays";
  std::ofstream(bad, std::ios::binary) << "not a multiple of 32 bytes";
  const auto result = run_cli({"trace", c.ply.string(), bad.string()});
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_NE(result.err.find("bad.rays"), std::string::npos) << result.err;
}

TEST(CliRender, WritesPng) {
  const SmallCase c = make_small_case();
  const auto png = c.dir / "img.png";
  const auto result = run_cli({"render", c.ply.string(), "--accel", "brute_force", "--res", "24x16", "--eye",
                               "0,0,5", "--at", "0,0,0", "--up", "0,1,0", "--fov", "50", "--out", png.string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_TRUE(std::filesystem::exists(png));
  EXPECT_GT(std::filesystem::file_size(png), 0u);
}

TEST(CliRender, WhittedWritesImageSamplesMapAndRayCounts) {
  const auto dir = fresh_directory("whitted");
  const auto png = dir / "glass.png", spp = dir / "spp.png", json_path = dir / "glass.json";
  const std::vector<std::string> base = {"render", "builtin:glass:level=2", "--mode", "whitted", "--res", "40x30",
                                         "--eye", "0,2.5,5", "--at", "0,0.8,0"};
  std::vector<std::string> args = base;
  args.insert(args.end(), {"--aa", "adaptive:threshold=0.05,max_level=2", "--out", png.string(), "--spp-map",
                           spp.string(), "--json", json_path.string()});
  const auto result = run_cli(args);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_TRUE(std::filesystem::exists(png));
  EXPECT_TRUE(std::filesystem::exists(spp));
  const nlohmann::json report = nlohmann::json::parse(testing::read_file(json_path));
  EXPECT_GT(report["refraction_rays"].get<int>(), 0);
  EXPECT_GT(report["shadow_rays"].get<int>(), 0);
  EXPECT_GT(report["samples_per_pixel"].get<double>(), 1.0);  // the ball's silhouette got subdivided
  EXPECT_LT(report["samples_per_pixel"].get<double>(), 25.0);
  EXPECT_EQ(report["rays"], report["camera_rays"].get<int>() + report["shadow_rays"].get<int>() +
                                report["reflection_rays"].get<int>() + report["refraction_rays"].get<int>());
  // Against itself as the reference: no error.
  args = base;
  args.insert(args.end(), {"--aa", "adaptive:threshold=0.05,max_level=2", "--out", (dir / "again.png").string(),
                           "--reference", png.string()});
  const auto again = run_cli(args);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.out.find("RMSE 0.000"), std::string::npos) << again.out;
}

}  // namespace
}  // namespace rayaccel
