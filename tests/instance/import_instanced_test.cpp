// import_instanced_scene(): a glTF file written here, with one mesh placed by three nodes (one of them the child of
// a translated and scaled parent), reads as one geometry and three instances whose flattening is what
// import_mesh() makes of the same file.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "gltf_file.h"
#include "rayaccel/core/error.h"
#include "rayaccel/instance/flatten.h"
#include "rayaccel/instance/import_instanced.h"
#include "rayaccel/scene/import.h"

namespace rayaccel {
namespace {

/// One triangle, used by node 0 (at the origin), node 1 (translated by x = 5) and node 2, the child of node 1
/// scaled by 2 and translated by y = 3 in its parent's space.
std::filesystem::path write_gltf() {
  const std::array<float, 9> positions{0, 0, 0, 1, 0, 0, 0, 1, 0};
  const auto path = std::filesystem::temp_directory_path() / ("rayaccel_instanced_" + std::to_string(::getpid()) + ".gltf");
  testing::write_gltf(path, positions, "[0, 1]", R"([
    {"mesh": 0},
    {"mesh": 0, "translation": [5, 0, 0], "children": [2]},
    {"mesh": 0, "translation": [0, 3, 0], "scale": [2, 2, 2]}
  ])");
  return path;
}

TEST(ImportInstanced, NodesBecomeInstancesOfOneGeometry) {
#ifndef RAYACCEL_TEST_WITH_ASSIMP
  GTEST_SKIP() << "built without assimp: only PLY files are read";
#endif
  const auto path = write_gltf();
  const InstancedScene scene = import_instanced_scene(path);
  ASSERT_EQ(scene.geometry_count(), 1u);
  ASSERT_EQ(scene.instance_count(), 3u);
  EXPECT_EQ(scene.geometry(0).primitive_count(), 1u);
  EXPECT_DOUBLE_EQ(scene.instance(1).transform(0, 3), 5.0);
  EXPECT_DOUBLE_EQ(scene.instance(2).transform(0, 0), 2.0);  // the child: parent translation, then its own
  EXPECT_DOUBLE_EQ(scene.instance(2).transform(1, 3), 3.0);
  EXPECT_DOUBLE_EQ(scene.instance(2).transform(0, 3), 5.0);
  EXPECT_EQ(scene.instance(2).instance_id, 2u);

  // Flattened, it is what import_mesh() reads: the same triangles in the same order.
  const FlattenedScene flat = flatten(scene);
  const TriangleMesh mesh = import_mesh(path);
  ASSERT_EQ(flat.scene.primitive_count(), mesh.triangles.size());
  for (std::uint32_t t = 0; t < flat.scene.primitive_count(); ++t) {
    const auto tri = flat.scene.triangle(t);
    for (int k = 0; k < 3; ++k) {
      const Vec3& expected = mesh.vertices[mesh.triangles[t][static_cast<std::size_t>(k)]];
      EXPECT_EQ(tri[static_cast<std::size_t>(k)].x, expected.x);
      EXPECT_EQ(tri[static_cast<std::size_t>(k)].y, expected.y);
      EXPECT_EQ(tri[static_cast<std::size_t>(k)].z, expected.z);
    }
  }
  std::filesystem::remove(path);
}

TEST(ImportInstanced, PlyIsOneInstanceAndBadFilesAreErrors) {
  const auto path = std::filesystem::temp_directory_path() / ("rayaccel_instanced_" + std::to_string(::getpid()) + ".ply");
  std::ofstream(path) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                         "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const InstancedScene scene = import_instanced_scene(path);
  EXPECT_EQ(scene.geometry_count(), 1u);
  EXPECT_EQ(scene.instance_count(), 1u);
  std::filesystem::remove(path);
  EXPECT_THROW(import_instanced_scene(path), Error);  // gone
}

}  // namespace
}  // namespace rayaccel
