// Slow tier: the shared benchmark meshes load with the counts and bounds that ../shared/scenes/MANIFEST.md lists.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>

#include "../shared_scenes.h"
#include "rayaccel/scene/import.h"

namespace rayaccel {
namespace {

struct ManifestEntry {
  const char* file;
  std::uint32_t triangles;
  std::size_t vertices;
  std::uint32_t zero_area;
  Vec3 lo, hi;
};

const ManifestEntry kManifest[] = {
    {"bunny.ply", 69451, 35947, 0, {-0.09469f, 0.032987f, -0.061874f}, {0.061009f, 0.187321f, 0.0588f}},
    {"dragon.ply", 871414, 437645, 108, {-0.108324f, 0.0527295f, -0.0504143f}, {0.0965662f, 0.197173f, 0.0412075f}},
    {"crytek_sponza.ply", 262205, 165046, 1, {-192.095f, -12.6443f, -118.281f}, {179.991f, 142.943f, 110.543f}},
    {"conference.ply", 331179, 194399, 53627, {-1020.13f, -2.7924f, -1055.66f}, {1685.81f, 650.293f, 668.489f}},
};

TEST(SlowSharedScenes, LoadWithTheManifestCounts) {
  const std::filesystem::path dir = testing::shared_scenes_dir();
  for (const auto& m : kManifest) RAYACCEL_NEED_SHARED_FILE(dir / m.file);
  for (const auto& m : kManifest) {
    SCOPED_TRACE(m.file);
    const Scene scene = load_scene((dir / m.file).string());
    EXPECT_EQ(scene.name(), std::filesystem::path(m.file).stem().string());
    EXPECT_EQ(scene.primitive_count(), m.triangles);
    EXPECT_EQ(scene.mesh().vertices.size(), m.vertices);
    EXPECT_EQ(scene.invalid_count(), 0u);
    EXPECT_EQ(scene.degenerate_count(), m.zero_area);
    // The manifest prints 6 significant digits.
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(scene.bounds().lo[a], m.lo[a], 1e-5f * (1.0f + std::fabs(m.lo[a])));
      EXPECT_NEAR(scene.bounds().hi[a], m.hi[a], 1e-5f * (1.0f + std::fabs(m.hi[a])));
    }
  }
}

}  // namespace
}  // namespace rayaccel
