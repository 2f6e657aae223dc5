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
#include "rayaccel/accel/brute_force.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/render/colormap.h"
#include "rayaccel/render/image_compare.h"
#include "rayaccel/scene/import.h"
#include "rayaccel/scene/ray_io.h"
#include "rayaccel/version.h"

namespace rayaccel {
namespace {

using testing::fresh_directory;
using testing::last_nonempty_line;
using testing::run_cli;

/// Writes a binary little-endian PLY in the format of shared/scenes (float xyz, uchar-count int faces).
void write_ply(const std::filesystem::path& path, const TriangleMesh& mesh) {
  std::ofstream out(path, std::ios::binary);
  out << "ply\nformat binary_little_endian 1.0\nelement vertex " << mesh.vertices.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << mesh.triangles.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Vec3& v : mesh.vertices) out.write(reinterpret_cast<const char*>(&v), sizeof(v));
  for (const auto& t : mesh.triangles) {
    const unsigned char three = 3;
    out.write(reinterpret_cast<const char*>(&three), 1);
    for (std::uint32_t i : t) {
      const std::int32_t index = static_cast<std::int32_t>(i);
      out.write(reinterpret_cast<const char*>(&index), sizeof(index));
    }
  }
}

/// 300 random triangles in [-1, 1]^3, then a copy of triangle 5 (ties in t) and a zero-area triangle.
TriangleMesh small_mesh() {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  TriangleMesh mesh;
  for (std::uint32_t i = 0; i < 300; ++i) {
    const Vec3 center{u(rng), u(rng), u(rng)};
    for (int k = 0; k < 3; ++k) mesh.vertices.push_back(center + Vec3{u(rng), u(rng), u(rng)} * 0.25f);
    mesh.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  mesh.triangles.push_back(mesh.triangles[5]);
  const auto n = static_cast<std::uint32_t>(mesh.vertices.size());
  mesh.vertices.push_back({0.0f, 0.0f, 0.0f});
  mesh.vertices.push_back({1.0f, 1.0f, 1.0f});
  mesh.vertices.push_back({2.0f, 2.0f, 2.0f});
  mesh.triangles.push_back({n, n + 1, n + 2});
  return mesh;
}

/// Rays aimed at triangle centroids (some with a shortened t_max or a raised t_min) and random rays.
std::vector<Ray> small_rays(const TriangleMesh& mesh) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  std::uniform_int_distribution<std::size_t> pick(0, mesh.triangles.size() - 1);
  std::vector<Ray> rays;
  for (int i = 0; i < 600; ++i) {
    Ray r;
    r.origin = {u(rng), u(rng), u(rng)};
    if (i % 5 == 4) {
      r.direction = {u(rng), u(rng), u(rng)};
    } else {
      const auto& t = mesh.triangles[pick(rng)];
      const Vec3 target = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) * (1.0f / 3.0f);
      r.direction = target - r.origin;
    }
    if (i % 7 == 3) r.t_max = 0.6f;
    if (i % 11 == 2) r.t_min = 0.4f;
    rays.push_back(r);
  }
  return rays;
}

struct SmallCase {
  std::filesystem::path dir, ply, rays;
  TriangleMesh mesh;
};

SmallCase make_small_case() {
  SmallCase c;
  c.dir = fresh_directory("case");
  c.ply = c.dir / "small.ply";
  c.rays = c.dir / "small.rays";
  c.mesh = small_mesh();
  write_ply(c.ply, c.mesh);
  write_rays(c.rays, small_rays(c.mesh));
  return c;
}

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
  // The default ray kinds, in the table's order: Mrays/s per kind, then nodes/prims per kind except the packet ones.
  std::size_t at = 0;
  for (const char* column : {"primary Mrays/s", "diffuse Mrays/s", "shadow Mrays/s", "occlusion Mrays/s",
                             "light Mrays/s", "packet Mrays/s", "light_packet Mrays/s", "primary nodes/prims",
                             "diffuse nodes/prims",
                             "shadow nodes/prims", "occlusion nodes/prims", "light nodes/prims", "mismatches"}) {
    const std::size_t found = result.out.find(column, at);
    ASSERT_NE(found, std::string::npos) << column << " after column " << at << " in\n" << result.out;
    at = found;
  }
  EXPECT_EQ(result.out.find("packet nodes/prims"), std::string::npos) << result.out;  // light_packet's included
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
  EXPECT_NE(result.out.find("packet Mrays/s"), std::string::npos) << result.out;
  EXPECT_EQ(result.out.find("primary Mrays/s"), std::string::npos) << result.out;
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

}  // namespace
}  // namespace rayaccel
