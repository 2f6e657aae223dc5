// End-to-end tests of `rayaccel bench`: the tables and JSON of a small run, images on one colour scale, packet rays,
// sphere scenes, the defaults (the default structure alone unless --accel all), narrow tables, and the HTML report.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "small_case.h"
#include "rayaccel/render/colormap.h"
#include "rayaccel/render/image_compare.h"
#include "rayaccel/scene/import.h"

namespace rayaccel {
namespace {

using testing::fresh_directory;
using testing::make_small_case;
using testing::run_cli;
using testing::SmallCase;

/// The first line of `out` that starts with `start` (a table's header), empty when there is none.
std::string header_line(const std::string& out, const std::string& start) {
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind(start, 0) == 0) return line;
  }
  return {};
}

TEST(CliBench, SmallRunWritesJsonAndImages) {
  const SmallCase c = make_small_case();
  const auto json_path = c.dir / "bench.json";
  const auto images = c.dir / "images";
  std::vector<std::string> args = {"bench", c.ply.string(), "--accel", "brute_force", "--res", "16", "--repeat",
                                   "1", "--json", json_path.string(), "--images", images.string()};
#ifdef RAYACCEL_HAVE_EMBREE
  args.insert(args.end(), {"--compare", "embree"});
#endif
  const auto result = run_cli(args);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("brute_force"), std::string::npos) << result.out;
  // Three tables: build and memory (with the verdict), Mrays/s per ray kind in order, nodes/prims per kind except
  // the packet ones.
  std::size_t at = 0;
  for (const char* column : {"build ms", "with input MB", "mismatches", "\nMrays/s", "primary", "diffuse", "shadow",
                             "occlusion", "light", "packet", "light_packet", "\nnodes/prims per ray", "primary",
                             "diffuse", "shadow", "occlusion", "light"}) {
    const std::size_t found = result.out.find(column, at);
    ASSERT_NE(found, std::string::npos) << column << " after column " << at << " in\n" << result.out;
    at = found;
  }
  EXPECT_EQ(header_line(result.out, "nodes/prims per ray").find("packet"), std::string::npos) << result.out;
  const nlohmann::json report = nlohmann::json::parse(testing::read_file(json_path));
  const auto& rows = report["scenes"][0]["results"];
  bool saw_brute_force = false;
  for (const auto& row : rows) {
    EXPECT_EQ(row["rays"].size(), 7u) << row.dump();
    if (row["accel"] != "brute_force") continue;
    saw_brute_force = true;
    EXPECT_EQ(row["mismatches"], 0);
    EXPECT_GT(row["rays"]["primary"]["checked"].get<int>(), 0);
    EXPECT_EQ(row["rays"]["primary"]["rays"], 256);
    // Brute force tests every valid (finite, non-degenerate) primitive once per ray.
    EXPECT_DOUBLE_EQ(row["rays"]["primary"]["primitives_tested_per_ray"].get<double>(),
                     double(load_scene(c.ply.string()).valid_count()));
    EXPECT_EQ(row["rays"]["packet"]["rays"], 256);
    EXPECT_GT(row["rays"]["packet"]["checked"].get<int>(), 0);
    EXPECT_EQ(row["rays"]["packet"]["mismatches"], 0);
    EXPECT_GT(row["rays"]["packet"]["mrays_s_median"].get<double>(), 0.0);
    EXPECT_FALSE(row["rays"]["packet"].contains("nodes_per_ray")) << "packet traversals take no statistics";
    // The light rays in tile order: as many as the light kind's (one per primary hit), checked like them.
    EXPECT_EQ(row["rays"]["light_packet"]["rays"], row["rays"]["light"]["rays"]);
    EXPECT_GT(row["rays"]["light_packet"]["checked"].get<int>(), 0);
    EXPECT_EQ(row["rays"]["light_packet"]["mismatches"], 0);
    EXPECT_FALSE(row["rays"]["light_packet"].contains("nodes_per_ray"));
  }
  EXPECT_TRUE(saw_brute_force);
  // Memory on the same terms for every row: the structure's own bytes, and the input its queries read.
  const Scene scene = load_scene(c.ply.string());
  for (const auto& row : rows) {
    if (row["accel"] == "brute_force") {
      EXPECT_EQ(row["input_memory_bytes"], scene.memory_bytes());
    }
    if (row["accel"] == "embree") {  // Embree's padded vertex copy and the index buffer of the valid triangles
      ASSERT_LT(scene.valid_count(), scene.primitive_count()) << "the case should hold an invalid triangle";
      EXPECT_EQ(row["input_memory_bytes"], (3 * scene.mesh().vertices.size() + 1) * sizeof(float) +
                                               scene.valid_count() * 3 * sizeof(std::uint32_t));
      EXPECT_GT(row["memory_bytes"].get<std::size_t>(), 0u);
      // Embree's own answers are checked on brute force's sample, by the rule for a foreign kernel.
      EXPECT_EQ(row["rays"]["primary"]["checked"], 256);
      EXPECT_EQ(row["rays"]["primary"]["foreign_differences"], 0);
    }
  }
  EXPECT_NE(result.out.find("with input MB"), std::string::npos) << result.out;
#ifdef RAYACCEL_HAVE_EMBREE
  EXPECT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0]["accel"], "embree");
#endif
  EXPECT_TRUE(std::filesystem::exists(images / "small_brute_force_normals.png"));
  EXPECT_TRUE(std::filesystem::exists(images / "small_brute_force_heatmap.png"));
}

/// The pixels of a PNG file, row by row.
std::vector<Rgb> read_png(const std::filesystem::path& path) {
  const Image image = load_png(path);
  std::vector<Rgb> pixels(static_cast<std::size_t>(image.width) * image.height);
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    pixels[i] = {image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2]};
  }
  return pixels;
}

TEST(CliBench, HeatMapsOfOneRunShareOneColourScale) {
  const SmallCase c = make_small_case();
  const auto heat_map = [&](const std::string& accel, const std::string& dir, std::vector<std::string> extra) {
    std::vector<std::string> args = {"bench", c.ply.string(), "--accel", accel, "--res", "16", "--rays", "primary",
                                     "--repeat", "1", "--images", (c.dir / dir).string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto result = run_cli(args);
    EXPECT_EQ(result.exit_code, 0) << result.err;
    return read_png(c.dir / dir / "small_brute_force_heatmap.png");
  };
  // Alone, brute force's rays all cost the same: its own scale is one value and its misses show the middle of the
  // ramp (hits are darkened by their angle).
  const std::vector<Rgb> alone = heat_map("brute_force", "alone", {});
  ASSERT_EQ(alone.size(), 256u);
  std::vector<std::size_t> misses;
  for (std::size_t i = 0; i < alone.size(); ++i) {
    if (alone[i] == heat_colour(0.5f)) misses.push_back(i);
  }
  ASSERT_FALSE(misses.empty());
  // Beside a BVH, whose rays cost less, the run's one scale places brute force elsewhere on the ramp.
  const std::vector<Rgb> shared = heat_map("brute_force,bvh", "shared", {});
  ASSERT_EQ(shared.size(), 256u);
  EXPECT_TRUE(std::filesystem::exists(c.dir / "shared" / "small_bvh_heatmap.png"));
  for (const std::size_t i : misses) {
    EXPECT_EQ(shared[i], shared[misses.front()]) << i;
    EXPECT_NE(shared[i], heat_colour(0.5f)) << i;
  }
  // --heat-max 1 puts every cost of 1 or more at the top of the ramp.
  const std::vector<Rgb> fixed = heat_map("brute_force", "fixed", {"--heat-max", "1"});
  ASSERT_EQ(fixed.size(), 256u);
  for (const std::size_t i : misses) EXPECT_EQ(fixed[i], heat_colour(1.0f)) << i;
}

TEST(CliBench, TooManyHeatMapsForOneScaleAskForHeatMaxBeforeWorking) {
  const SmallCase c = make_small_case();
  const auto images = c.dir / "big_images";
  const auto result =
      run_cli({"bench", c.ply.string(), "--accel", "all", "--res", "8192", "--images", images.string()});
  EXPECT_EQ(result.exit_code, 2) << result.err;
  EXPECT_NE(result.err.find("--heat-max"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(images));
}

TEST(CliBench, PacketRaysAloneAreTracedAndChecked) {
  const SmallCase c = make_small_case();
  const auto json_path = c.dir / "bench_packet.json";
  // 10 x 10 is not a multiple of the 4 x 2 tiles: the pixels outside whole tiles are traced too.
  std::vector<std::string> args = {"bench", c.ply.string(), "--accel", "brute_force,bvh_wide,grid", "--rays",
                                   "packet", "--res", "10", "--repeat", "1", "--json", json_path.string()};
#ifdef RAYACCEL_HAVE_EMBREE
  args.insert(args.end(), {"--compare", "embree"});
#endif
  const auto result = run_cli(args);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(header_line(result.out, "Mrays/s").find("packet"), std::string::npos) << result.out;
  EXPECT_EQ(header_line(result.out, "Mrays/s").find("primary"), std::string::npos) << result.out;
  EXPECT_EQ(result.out.find("nodes/prims"), std::string::npos) << result.out;
  const nlohmann::json report = nlohmann::json::parse(testing::read_file(json_path));
  const auto& rows = report["scenes"][0]["results"];
#ifdef RAYACCEL_HAVE_EMBREE
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0]["accel"], "embree");
  EXPECT_NE(result.out.find("x)"), std::string::npos) << "ratios to Embree expected:\n" << result.out;
#else
  ASSERT_EQ(rows.size(), 3u);
#endif
  for (const auto& row : rows) {
    ASSERT_EQ(row["rays"].size(), 1u) << row.dump();
    const auto& packet = row["rays"]["packet"];
    EXPECT_EQ(packet["rays"], 100);
    EXPECT_GT(packet["mrays_s_median"].get<double>(), 0.0);
    if (row["is_embree"]) continue;
    EXPECT_EQ(packet["checked"], 100) << row["accel"];
    EXPECT_EQ(packet["mismatches"], 0) << row["accel"];
  }
}

TEST(CliBench, SkipKindsAreTracedUnderTheirContextAndChecked) {
  const SmallCase c = make_small_case();
  const auto json_path = c.dir / "bench_skip.json";
  std::vector<std::string> args = {"bench", c.ply.string(), "--accel", "brute_force,bvh_wide,grid", "--rays",
                                   "occlusion,diffuse_skip,shadow_skip,occlusion_skip,light_skip", "--res", "12",
                                   "--repeat", "1", "--json", json_path.string()};
#ifdef RAYACCEL_HAVE_EMBREE
  args.insert(args.end(), {"--compare", "embree"});
#endif
  const auto result = run_cli(args);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json report = nlohmann::json::parse(testing::read_file(json_path));
  const auto& rows = report["scenes"][0]["results"];
#ifdef RAYACCEL_HAVE_EMBREE
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0]["accel"], "embree:filter=1") << "the skip queries need Embree's context filter";
  EXPECT_NE(result.out.find("x)"), std::string::npos) << "ratios to Embree expected:\n" << result.out;
#else
  ASSERT_EQ(rows.size(), 3u);
#endif
  for (const auto& row : rows) {
    ASSERT_EQ(row["rays"].size(), 5u) << row.dump();
    EXPECT_EQ(row["rays"]["occlusion_skip"]["rays"], row["rays"]["occlusion"]["rays"]) << "the same rays";
    for (const char* kind : {"diffuse_skip", "shadow_skip", "occlusion_skip", "light_skip"}) {
      const auto& k = row["rays"][kind];
      EXPECT_GT(k["rays"].get<int>(), 0) << kind;
      EXPECT_GT(k["mrays_s_median"].get<double>(), 0.0) << kind;
      EXPECT_FALSE(k.contains("nodes_per_ray")) << "queries with a context take no statistics";
      if (row["is_embree"]) continue;
      EXPECT_EQ(k["checked"], k["rays"]) << row["accel"] << " " << kind;
      EXPECT_EQ(k["mismatches"], 0) << row["accel"] << " " << kind;
    }
  }
}

TEST(CliBench, SphereSceneIsCheckedAgainstBruteForceSample) {
  const auto dir = fresh_directory("spheres");
  const auto json_path = dir / "bench.json";
  std::vector<std::string> args = {"bench", "builtin:sphereflake:level=1", "--accel", "brute_force,grid",
                                   "--res", "8", "--repeat", "1", "--json", json_path.string()};
#ifdef RAYACCEL_HAVE_EMBREE
  args.insert(args.end(), {"--compare", "embree"});
#endif
  const auto result = run_cli(args);
  ASSERT_EQ(result.exit_code, 0) << result.err;
#ifdef RAYACCEL_HAVE_EMBREE
  EXPECT_NE(result.err.find("triangle scenes only"), std::string::npos) << result.err;
#endif
  const nlohmann::json scene = nlohmann::json::parse(testing::read_file(json_path))["scenes"][0];
  EXPECT_EQ(scene["kind"], "spheres");
  EXPECT_NE(scene["reference"].get<std::string>().find("brute force"), std::string::npos);
  ASSERT_EQ(scene["results"].size(), 2u);
  EXPECT_EQ(scene["results"][1]["accel"], "grid");
  EXPECT_EQ(scene["results"][1]["mismatches"], 0);
  EXPECT_EQ(scene["results"][1]["rays"]["primary"]["checked"], 64);
}

TEST(CliBench, DefaultsToTheDefaultStructureAlone) {
  const SmallCase c = make_small_case();
  const auto json_path = c.dir / "default.json";
  const auto rows_of = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = {"bench", c.ply.string(), "--res", "8", "--repeat", "1", "--rays", "primary",
                                     "--json", json_path.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto result = run_cli(args);
    EXPECT_EQ(result.exit_code, 0) << result.err;
    return nlohmann::json::parse(testing::read_file(json_path))["scenes"][0]["results"];
  };
  const auto alone = rows_of({});
  ASSERT_EQ(alone.size(), 1u) << alone.dump();
  const std::string structure = alone[0]["accel"];
  EXPECT_NE(structure, "brute_force");
  EXPECT_FALSE(alone[0]["is_embree"].get<bool>());
  const auto help = run_cli({"bench", "--help"});
  EXPECT_NE(help.out.find("default structure, " + structure), std::string::npos) << help.out;
#ifdef RAYACCEL_HAVE_EMBREE
  const auto compared = rows_of({"--compare", "embree"});
  ASSERT_EQ(compared.size(), 2u) << compared.dump();
  EXPECT_EQ(compared[0]["accel"], "embree");
  EXPECT_EQ(compared[1]["accel"], structure);
#endif
}

TEST(CliBench, TablesFitATerminal) {
  const SmallCase c = make_small_case();
  std::vector<std::string> args = {"bench", c.ply.string(), "--accel", "kdtree:builder=sah,mailbox=false,bvh_wide",
                                   "--res", "8", "--repeat", "1"};
#ifdef RAYACCEL_HAVE_EMBREE
  args.insert(args.end(), {"--compare", "embree"});
#endif
  const auto result = run_cli(args);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::istringstream lines(result.out);
  std::size_t widest = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("  ", 0) == 0) continue;  // a structure's build statistics, one line each
    widest = std::max(widest, line.size());
  }
  EXPECT_LE(widest, 150u) << result.out;
}

TEST(CliRender, UnknownModeListsEveryMode) {
  const SmallCase c = make_small_case();
  const auto result = run_cli({"render", c.ply.string(), "--mode", "whited", "--out", (c.dir / "x.png").string()});
  EXPECT_EQ(result.exit_code, 2) << result.err;
  EXPECT_NE(result.err.find("'whited'"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("normals, ao, heatmap, whitted"), std::string::npos) << result.err;
  const auto help = run_cli({"render", "--help"});
  EXPECT_NE(help.out.find("whitted"), std::string::npos) << help.out;
}

}  // namespace
}  // namespace rayaccel
