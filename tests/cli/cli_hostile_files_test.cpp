// End-to-end tests of the CLI on the hostile inputs of issue #40: a glTF node chain deep enough to overflow assimp's
// recursion, PLY first lines other than "ply" that used to reach assimp's PLY loader (and hang there), MANIFEST.md
// side files that are FIFOs, devices or huge, 50,000 coincident triangles under the PLOC builder, camera messages
// that name where the bad value came from, and runs with several outputs that wrote some before failing. Every run
// is bounded by timeout(1).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_runner.h"

namespace rayaccel {
namespace {

using testing::CommandResult;
using testing::fresh_directory;
using testing::run_cli_bounded;
using testing::some_rays;

using testing::kSphereScene;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// A glTF 2 file whose nodes form one chain `depth` deep (node i's child is i + 1); no meshes.
std::filesystem::path node_chain_gltf(const std::filesystem::path& dir, int depth) {
  const auto file = dir / ("chain" + std::to_string(depth) + ".gltf");
  std::ofstream out(file);
  out << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[)";
  for (int i = 0; i < depth; ++i) {
    out << (i > 0 ? "," : "");
    if (i + 1 < depth) out << R"({"children":[)" << i + 1 << "]}";
    else out << "{}";
  }
  out << "]}";
  return file;
}

/// An ASCII PLY of `copies` copies of one triangle.
std::filesystem::path same_triangles(const std::filesystem::path& dir, int copies) {
  const auto file = dir / ("same" + std::to_string(copies) + ".ply");
  std::ofstream out(file);
  out << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      << "element face " << copies << "\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
  for (int i = 0; i < copies; ++i) out << "3 0 1 2\n";
  return file;
}

TEST(CliHostileFiles, DeepGltfNodeChainIsRefusedNamingTheDepth) {
  const auto dir = fresh_directory("deep");
  const auto deep = node_chain_gltf(dir, 20000);  // crashed assimp's glTF reader (SIGSEGV, ~35,000 frames)
  const auto result = run_cli_bounded({"info", deep.string()});
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_TRUE(contains(result.err, "chain20000.gltf")) << result.err;
  EXPECT_TRUE(contains(result.err, "20000 levels deep")) << result.err;
  // A shallow chain passes the check and reaches assimp (which finds no triangles in it).
  const auto shallow = run_cli_bounded({"info", node_chain_gltf(dir, 10).string()});
  EXPECT_EQ(shallow.exit_code, 1) << shallow.err;
  EXPECT_FALSE(contains(shallow.err, "levels deep")) << shallow.err;
}

TEST(CliHostileFiles, GltfNodeCycleIsRefused) {
  const auto dir = fresh_directory("cycle");
  const auto file = dir / "cycle.gltf";
  std::ofstream(file) << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],)"
                      << R"("nodes":[{"children":[1]},{"children":[2]},{"children":[1]}]})";
  const auto result = run_cli_bounded({"info", file.string()});
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_TRUE(contains(result.err, "cycle.gltf")) << result.err;
  EXPECT_TRUE(contains(result.err, "two nodes") || contains(result.err, "cycle")) << result.err;
}

TEST(CliHostileFiles, EveryPlyFirstLineReachesOurReaderNotAHang) {
  const auto dir = fresh_directory("ply");
  // First lines assimp's PLY loader took (and looped on, the header being cut short), and a non-PLY called .ply.
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"upper.ply", "PLY\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"},
      {"space.ply", "ply \nformat ascii 1.0\nelement vertex 3\nproperty float x\n"},
      {"cr.ply", "ply\rformat ascii 1.0\relement vertex 3\rproperty float x\r"},
      {"cr_named.dat", "ply\rformat ascii 1.0\relement vertex 3\rproperty float x\r"},
      {"not_a_ply.ply", "solid x\nfacet normal 0 0 1\n"},
  };
  for (const auto& [name, text] : cases) {
    const auto file = dir / name;
    std::ofstream(file, std::ios::binary) << text;
    const auto result = run_cli_bounded({"info", file.string()}, 20);
    EXPECT_EQ(result.exit_code, 1) << name << ": " << result.err;
    EXPECT_TRUE(contains(result.err, "PLY file")) << name << ": " << result.err;
    EXPECT_TRUE(contains(result.err, name)) << name << ": " << result.err;
  }
  // A file that is no PLY but has "ply" in its first bytes went to assimp's PLY loader by that token; no more.
  const auto junk = dir / "junk.txt";
  std::ofstream(junk, std::ios::binary) << "comment ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n";
  const auto result = run_cli_bounded({"info", junk.string()}, 20);
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_FALSE(contains(result.err, ".ply file")) << "reached assimp's PLY loader: " << result.err;
}

TEST(CliHostileFiles, ManifestThatIsNotARegularFileIsRefusedNotRead) {
  const auto dir = fresh_directory("manifest");
  const auto mesh = same_triangles(dir, 1);
  const auto manifest = dir / "MANIFEST.md";
  const auto render = [&] {
    return run_cli_bounded({"render", mesh.string(), "--res", "4x4", "--out", (dir / "x.png").string()}, 30);
  };
  ASSERT_EQ(::mkfifo(manifest.c_str(), 0600), 0);  // blocked render forever
  auto result = render();
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_TRUE(contains(result.err, "MANIFEST.md") && contains(result.err, "not a regular file")) << result.err;
  std::filesystem::remove(manifest);
  if (std::filesystem::exists("/dev/zero")) {  // read until memory ran out
    std::filesystem::create_symlink("/dev/zero", manifest);
    result = render();
    EXPECT_EQ(result.exit_code, 1) << result.err;
    EXPECT_TRUE(contains(result.err, "not a regular file")) << result.err;
    std::filesystem::remove(manifest);
  }
  { std::ofstream(manifest) << "x"; }
  std::filesystem::resize_file(manifest, (1 << 20) + 1);
  result = render();
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_TRUE(contains(result.err, "MANIFEST.md") && contains(result.err, "larger than 1 MiB")) << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.png"));
  const auto help = run_cli_bounded({"render", "--help"});
  EXPECT_TRUE(contains(help.out, "MANIFEST.md")) << "render --help must say it reads MANIFEST.md: " << help.out;
}

TEST(CliHostileFiles, ManifestUpParallelToTheViewNamesFileAndLine) {
  const auto dir = fresh_directory("up");
  const auto mesh = same_triangles(dir, 1);
  std::ofstream(dir / "MANIFEST.md") << "# cameras\n\n```cameras\nsame1 eye=0,0,5 at=0,0,0 up=0,0,1 fov=40\n```\n";
  const auto result = run_cli_bounded({"render", mesh.string(), "--res", "4x4", "--out", (dir / "x.png").string()});
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_TRUE(contains(result.err, "MANIFEST.md:4")) << result.err;
  EXPECT_TRUE(contains(result.err, "parallel to the view")) << result.err;
}

TEST(CliHostileFiles, DefaultCameraOfATinySceneSaysWhyItCannotFrameIt) {
  const auto dir = fresh_directory("tiny");
  const auto file = dir / "tiny.ply";
  std::ofstream(file) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                      << "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                      << "0 0 0\n1e-40 0 0\n0 1e-40 0\n3 0 1 2\n";
  const auto result = run_cli_bounded({"render", file.string(), "--res", "4x4", "--out", (dir / "x.png").string()});
  EXPECT_EQ(result.exit_code, 2) << result.err;
  EXPECT_FALSE(contains(result.err, "--eye and --at are the same point")) << "neither was given: " << result.err;
  EXPECT_TRUE(contains(result.err, "default camera cannot frame")) << result.err;
}

TEST(CliHostileFiles, PlocBuildsFiftyThousandCoincidentTriangles) {
  // Coincident centroids made every PLOC round merge one pair: 6.5 s at 10,000 copies, over a minute at 50,000.
  const auto dir = fresh_directory("ploc");
  const auto mesh = same_triangles(dir, 50000);
  const auto rays = some_rays(dir);
  for (const char* bv : {"obb", "aabb", "sphere"}) {
    const std::string spec = std::string("bvh:bv=") + bv + ",builder=ploc";
    const auto result = run_cli_bounded({"trace", mesh.string(), rays.string(), "--accel", spec, "--repeat", "1"});
    EXPECT_EQ(result.exit_code, 0) << spec << ": " << result.err;
  }
}

TEST(CliHostileFiles, ReferenceOfAnotherSizeFailsBeforeAnyOutput) {
  const auto dir = fresh_directory("reference");
  const auto reference = dir / "ref4x4.png";
  ASSERT_EQ(run_cli_bounded({"render", kSphereScene, "--res", "4x4", "--out", reference.string()}).exit_code, 0);
  const auto old = dir / "old.png";
  for (const std::vector<std::string>& mode : {std::vector<std::string>{"--mode", "whitted"},
                                              std::vector<std::string>{"--cones", "shadows", "--accel", "bvh"}}) {
    std::ofstream(old) << "old";
    std::vector<std::string> args = {"render", kSphereScene, "--res", "8x8", "--reference", reference.string(), "--out",
                                     old.string()};
    args.insert(args.end(), mode.begin(), mode.end());
    const auto result = run_cli_bounded(args);
    EXPECT_NE(result.exit_code, 0) << mode[1];
    EXPECT_TRUE(contains(result.err, "ref4x4.png is 4x4")) << mode[1] << ": " << result.err;
    EXPECT_EQ(testing::read_file(old), "old") << mode[1] << ": the output was replaced before the run failed";
  }
}

TEST(CliHostileFiles, RunsCommitTheirOutputsAllOrNone) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const auto dir = fresh_directory("outputs");
  const auto png = dir / "a.png";
  for (const char* option : {"--json", "--spp-map"}) {  // the second output fails: the first must stay as it was
    std::ofstream(png) << "old";
    const auto result = run_cli_bounded(
        {"render", kSphereScene, "--mode", "whitted", "--res", "8x8", "--out", png.string(), option, "/dev/full"});
    EXPECT_EQ(result.exit_code, 1) << option << ": " << result.err;
    EXPECT_TRUE(contains(result.err, "No space left on device")) << option << ": " << result.err;
    EXPECT_EQ(testing::read_file(png), "old") << option << ": --out was replaced before the run failed";
  }
  const auto saved = dir / "s.bvh";
  std::ofstream(saved) << "old";
  const auto rays = some_rays(dir);
  const auto trace = run_cli_bounded({"trace", kSphereScene, rays.string(), "--accel", "bvh", "--repeat", "1", "--save",
                                      saved.string(), "--out", "/dev/full"});
  EXPECT_EQ(trace.exit_code, 1) << trace.err;
  EXPECT_EQ(testing::read_file(saved), "old") << "--save was replaced before the run failed";
  // No temporaries are left behind, and a run that succeeds writes every output.
  const auto ok = run_cli_bounded({"trace", kSphereScene, rays.string(), "--accel", "bvh", "--repeat", "1", "--save",
                                   saved.string(), "--out", (dir / "x.hits").string()});
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(testing::read_file(saved), "old");
  EXPECT_TRUE(std::filesystem::exists(dir / "x.hits"));
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    EXPECT_FALSE(contains(entry.path().filename().string(), ".tmp")) << entry.path();
  }
}

}  // namespace
}  // namespace rayaccel
