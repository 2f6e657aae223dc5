// GeometryTable: scene-wide primitive ids to (geometry id, primitive within the geometry) and back, and
// scene_from_meshes(), which merges meshes with each one's id.
#include "rayaccel/scene/geometry_table.h"

#include <gtest/gtest.h>

#include "rayaccel/core/error.h"

namespace rayaccel {
namespace {

TEST(GeometryTable, MapsPrimitivesToGeometriesAndBack) {
  GeometryTable table;
  EXPECT_EQ(table.add(3), 0u);
  EXPECT_EQ(table.add(0), 1u);  // an empty geometry owns no primitive
  EXPECT_EQ(table.add(2), 2u);
  EXPECT_EQ(table.geometry_count(), 3u);
  EXPECT_EQ(table.primitive_count(), 5u);
  const std::uint32_t geom[] = {0, 0, 0, 2, 2};
  const std::uint32_t local[] = {0, 1, 2, 0, 1};
  for (std::uint32_t p = 0; p < 5; ++p) {
    EXPECT_EQ(table.geometry_of(p), geom[p]) << p;
    EXPECT_EQ(table.local_primitive(p), local[p]) << p;
  }
  EXPECT_EQ(table.geometry_of(5), kInvalidPrimId);
  EXPECT_EQ(table.geometry_of(kInvalidPrimId), kInvalidPrimId);
  EXPECT_EQ(table.local_primitive(kInvalidPrimId), kInvalidPrimId);
  EXPECT_EQ(table.primitive_count(1), 0u);
  EXPECT_EQ(table.first_primitive(2), 3u);

  Hit hits[2];
  hits[0].prim_id = 4;
  std::uint32_t out[2];
  table.geometry_ids(hits, out);
  EXPECT_EQ(out[0], 2u);
  EXPECT_EQ(out[1], kInvalidPrimId);
  EXPECT_THROW(table.geometry_ids(hits, std::span<std::uint32_t>(out, 1)), Error);
  EXPECT_THROW(table.add(kInvalidPrimId - 5), Error);  // 5 + that would reach the miss marker
  EXPECT_EQ(table.geometry_count(), 3u);  // a failed add changes nothing
}

TEST(GeometryTable, SceneFromMeshesOffsetsEachMeshsIndices) {
  TriangleMesh a{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}};
  TriangleMesh b{{{0, 0, 5}, {1, 0, 5}, {0, 1, 5}, {1, 1, 5}}, {{0, 1, 2}, {1, 3, 2}}};
  GeometryTable table;
  const std::vector<TriangleMesh> meshes = {a, b};
  const Scene scene = scene_from_meshes(meshes, table);
  ASSERT_EQ(scene.primitive_count(), 3u);
  EXPECT_EQ(scene.triangle(2)[1].x, 1.0f);
  EXPECT_EQ(scene.triangle(2)[1].z, 5.0f);
  EXPECT_EQ(table.geometry_of(2), 1u);
  EXPECT_EQ(table.local_primitive(2), 1u);
  b.triangles.push_back({0, 1, 4});
  const std::vector<TriangleMesh> bad = {a, b};
  try {
    scene_from_meshes(bad, table);
    FAIL() << "no error for a vertex index out of range";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mesh 1: triangle 2 uses vertex index 4"), std::string::npos) << e.what();
  }
  EXPECT_EQ(table.geometry_count(), 2u);  // unchanged by the failed call
}

}  // namespace
}  // namespace rayaccel
