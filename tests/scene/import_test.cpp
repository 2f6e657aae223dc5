// Unit tests of mesh import and scene specs, on small files each test writes: file-order ids, fan triangulation,
// skipped points and lines, NaN vertices, and errors that name the file and the fault.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "rayaccel/core/error.h"
#include "rayaccel/scene/builtin_scenes.h"
#include "rayaccel/scene/import.h"
#include "temp_dir.h"

namespace rayaccel {
namespace {

using testing::TempDir;

/// The corner positions of triangle t.
std::array<Vec3, 3> corners(const TriangleMesh& mesh, std::size_t t) {
  const auto& tri = mesh.triangles[t];
  return {mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]};
}

void expect_error(const std::function<void()>& f, const std::string& file, const std::string& fault) {
  try {
    f();
    ADD_FAILURE() << "no error for " << file;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(fault), std::string::npos) << e.what();
  }
}

/// A binary little-endian PLY with float x, y, z and uchar/int face lists.
std::string binary_ply(const std::vector<Vec3>& vertices, const std::vector<std::vector<std::int32_t>>& faces) {
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by a test\nelement vertex " +
                    std::to_string(vertices.size()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(faces.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  auto put = [&out](const void* p, std::size_t n) {
    // Test machines are little-endian (x86-64, AArch64); the bytes are the file's own order.
    out.append(static_cast<const char*>(p), n);
  };
  for (const Vec3& v : vertices) {
    put(&v.x, 4);
    put(&v.y, 4);
    put(&v.z, 4);
  }
  for (const auto& f : faces) {
    const auto n = static_cast<unsigned char>(f.size());
    put(&n, 1);
    for (std::int32_t i : f) put(&i, 4);
  }
  return out;
}

const std::vector<Vec3> kSquare = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}};

TEST(ImportMesh, AsciiPlyKeepsFaceOrderAndFansPolygons) {
  TempDir dir;
  const auto file = dir.write("a.ply",
                              "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
                              "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
                              "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n4 0 1 2 3\n3 4 1 0\n");
  const TriangleMesh mesh = import_mesh(file);
  ASSERT_EQ(mesh.triangles.size(), 3u);
  EXPECT_EQ(corners(mesh, 0), (std::array<Vec3, 3>{kSquare[0], kSquare[1], kSquare[2]}));
  EXPECT_EQ(corners(mesh, 1), (std::array<Vec3, 3>{kSquare[0], kSquare[2], kSquare[3]}));
  EXPECT_EQ(corners(mesh, 2), (std::array<Vec3, 3>{kSquare[4], kSquare[1], kSquare[0]}));
}

TEST(ImportMesh, BinaryPlyKeepsIndicesAndOrder) {
  TempDir dir;
  const auto file = dir.write("b.ply", binary_ply(kSquare, {{2, 3, 4}, {0, 1, 2, 3}, {4, 0, 1}}));
  const TriangleMesh mesh = import_mesh(file);
  ASSERT_EQ(mesh.triangles.size(), 4u);
  EXPECT_EQ(corners(mesh, 0), (std::array<Vec3, 3>{kSquare[2], kSquare[3], kSquare[4]}));
  EXPECT_EQ(corners(mesh, 1), (std::array<Vec3, 3>{kSquare[0], kSquare[1], kSquare[2]}));
  EXPECT_EQ(corners(mesh, 2), (std::array<Vec3, 3>{kSquare[0], kSquare[2], kSquare[3]}));
  EXPECT_EQ(corners(mesh, 3), (std::array<Vec3, 3>{kSquare[4], kSquare[0], kSquare[1]}));
}

TEST(ImportMesh, ObjQuadBecomesTwoFanTrianglesAndPointsAndLinesAreSkipped) {
  TempDir dir;
  const auto file = dir.write("q.obj",
                              "# quad, then a point, a line and a triangle\n"
                              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
                              "f 1 2 3 4\np 5\nl 1 5\nf 5 2 1\n");
  const TriangleMesh mesh = import_mesh(file);
  ASSERT_EQ(mesh.triangles.size(), 3u);
  EXPECT_EQ(corners(mesh, 0), (std::array<Vec3, 3>{kSquare[0], kSquare[1], kSquare[2]}));
  EXPECT_EQ(corners(mesh, 1), (std::array<Vec3, 3>{kSquare[0], kSquare[2], kSquare[3]}));
  EXPECT_EQ(corners(mesh, 2), (std::array<Vec3, 3>{kSquare[4], kSquare[1], kSquare[0]}));
}

TEST(ImportMesh, ObjObjectsAreConcatenatedInFileOrder) {
  TempDir dir;
  const auto file = dir.write("two.obj",
                              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
                              "o first\nf 1 2 3\nf 1 3 4\no second\nf 5 1 2\n");
  const TriangleMesh mesh = import_mesh(file);
  ASSERT_EQ(mesh.triangles.size(), 3u);
  EXPECT_EQ(corners(mesh, 0), (std::array<Vec3, 3>{kSquare[0], kSquare[1], kSquare[2]}));
  EXPECT_EQ(corners(mesh, 1), (std::array<Vec3, 3>{kSquare[0], kSquare[2], kSquare[3]}));
  EXPECT_EQ(corners(mesh, 2), (std::array<Vec3, 3>{kSquare[4], kSquare[0], kSquare[1]}));

  // Each object is a geometry of its own, numbered in file order: the geometry ids of a plain scene.
  GeometryTable geometries;
  geometries.add(7);  // reset by the import
  const Scene scene = load_scene(file.string(), &geometries);
  ASSERT_EQ(geometries.geometry_count(), 2u);
  EXPECT_EQ(geometries.primitive_count(0), 2u);
  EXPECT_EQ(geometries.primitive_count(1), 1u);
  EXPECT_EQ(geometries.primitive_count(), scene.primitive_count());
}

TEST(ImportMesh, SceneGraphIsWalkedDepthFirstWithNodeTransforms) {
  // glTF: node 0 (mesh 0, moved +10 in x), node 1 (mesh 0 again, moved +20 in y) with a child (mesh 1, scaled 2).
  TempDir dir;
  const auto file = dir.write("graph.gltf",
      R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],)"
      R"("nodes":[{"mesh":0,"translation":[10,0,0]},)"
      R"({"mesh":0,"children":[2],"translation":[0,20,0]},{"mesh":1,"scale":[2,2,2]}],)"
      R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]},)"
      R"({"primitives":[{"attributes":{"POSITION":0},"indices":1,"mode":4}]}],)"
      R"("buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,)"
      R"(AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}],)"
      R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},)"
      R"({"buffer":0,"byteOffset":36,"byteLength":6}],)"
      R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},)"
      R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})");
  const TriangleMesh mesh = import_mesh(file);
  ASSERT_EQ(mesh.triangles.size(), 3u);
  EXPECT_EQ(corners(mesh, 0), (std::array<Vec3, 3>{Vec3{10, 0, 0}, Vec3{11, 0, 0}, Vec3{10, 1, 0}}));
  EXPECT_EQ(corners(mesh, 1), (std::array<Vec3, 3>{Vec3{0, 20, 0}, Vec3{1, 20, 0}, Vec3{0, 21, 0}}));
  EXPECT_EQ(corners(mesh, 2), (std::array<Vec3, 3>{Vec3{0, 20, 0}, Vec3{2, 20, 0}, Vec3{0, 22, 0}}));

  // One geometry per placed mesh, in the order of the hierarchy's placements (mesh 0 twice, then mesh 1).
  GeometryTable geometries;
  ASSERT_EQ(import_mesh(file, &geometries).triangles, mesh.triangles);
  const MeshHierarchy hierarchy = import_mesh_hierarchy(file);
  ASSERT_EQ(geometries.geometry_count(), hierarchy.placements.size());
  for (std::uint32_t g = 0; g < geometries.geometry_count(); ++g) {
    EXPECT_EQ(geometries.primitive_count(g), hierarchy.meshes[hierarchy.placements[g].mesh].triangles.size());
  }
  // A builtin scene and a PLY file are one geometry.
  EXPECT_EQ((load_scene("builtin:sphere", &geometries), geometries.geometry_count()), 1u);
}

TEST(ImportMesh, NanVertexIsKeptAndItsTrianglesAreInvalid) {
  TempDir dir;
  std::vector<Vec3> vertices = kSquare;
  vertices[4].y = std::nanf("");
  const auto file = dir.write("nan.ply", binary_ply(vertices, {{0, 1, 2}, {4, 1, 0}, {0, 2, 3}}));
  const TriangleMesh mesh = import_mesh(file);
  ASSERT_EQ(mesh.triangles.size(), 3u);
  EXPECT_TRUE(std::isnan(corners(mesh, 1)[0].y));
  const Scene scene = Scene::from_mesh(mesh);
  EXPECT_EQ(scene.invalid_count(), 1u);
  EXPECT_TRUE(scene.is_valid(0));
  EXPECT_FALSE(scene.is_valid(1));
  EXPECT_TRUE(scene.is_valid(2));

  // In text files assimp's number parser turns a vertex holding "nan" or "inf" into non-finite values too.
  const auto text =
      dir.write("nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nv 0 0 inf\nv 1 1 1\nf 1 2 3\nf 1 3 4\nf 3 1 2\nf 1 3 5\n");
  const Scene from_text = Scene::from_mesh(import_mesh(text));
  ASSERT_EQ(from_text.primitive_count(), 4u);
  EXPECT_EQ(from_text.invalid_count(), 3u);
  EXPECT_TRUE(from_text.is_valid(3));
}

TEST(ImportMesh, ErrorsNameTheFileAndTheFault) {
  TempDir dir;
  expect_error([&] { import_mesh(dir.path() / "absent.ply"); }, "absent.ply", "no such file");
  expect_error([&] { import_mesh(dir.path()); }, dir.path().string(), "not a regular file");
  const auto empty = dir.write("empty.ply", "");
  expect_error([&] { import_mesh(empty); }, "empty.ply", "not a mesh");
  const auto garbage = dir.write("garbage.ply", "ply\nformat ascii 1.0\nelement vertex banana\nend_header\n1 2 3\n");
  expect_error([&] { import_mesh(garbage); }, "garbage.ply", "count 'banana' is not a non-negative integer");
  const auto text = dir.write("notes.txt", "this is not a mesh at all\n");
  expect_error([&] { import_mesh(text); }, "notes.txt", "not a mesh");
  const auto points = dir.write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  expect_error([&] { import_mesh(points); }, "points.obj", "no triangles");
  const auto no_faces = dir.write("no_faces.ply", binary_ply(kSquare, {}));
  expect_error([&] { import_mesh(no_faces); }, "no_faces.ply", "no triangles");
  const auto lines = dir.write("lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n");
  expect_error([&] { import_mesh(lines); }, "lines.obj", "no triangles");
}

TEST(ImportMesh, OutOfRangeIndicesAreErrors) {
  TempDir dir;
  const auto ply = dir.write("range.ply", binary_ply(kSquare, {{0, 1, 2}, {0, 1, 5}}));
  expect_error([&] { import_mesh(ply); }, "range.ply", "vertex index 5, out of range");
  const auto negative = dir.write("negative.ply", binary_ply(kSquare, {{0, 1, -7}}));
  expect_error([&] { import_mesh(negative); }, "negative.ply", "out of range");
  const auto obj = dir.write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  expect_error([&] { import_mesh(obj); }, "range.obj", "out of range");
}

TEST(LoadScene, BuiltinSpecsAndFilesAreNamed) {
  const Scene sphere = load_scene("builtin:sphere:level=1,radius=3");
  EXPECT_EQ(sphere.name(), "sphere");
  EXPECT_EQ(sphere.primitive_count(), 80u);
  EXPECT_NEAR(sphere.bounds().hi.x, 3.0f, 1e-5f);
  EXPECT_EQ(load_scene("builtin:default").primitive_count(), load_scene(kDefaultSceneSpec).primitive_count());

  TempDir dir;
  const auto file = dir.write("little_quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  const Scene quad = load_scene(file.string());
  EXPECT_EQ(quad.name(), "little_quad");
  EXPECT_EQ(quad.primitive_count(), 2u);
}

TEST(LoadScene, BadSpecsAreErrors) {
  expect_error([] { load_scene("builtin:nope"); }, "'nope'", "sphereflake");
  expect_error([] { load_scene("builtin:sphere:levle=2"); }, "'levle'", "level");
  expect_error([] { load_scene("builtin:sphere:level"); }, "builtin:sphere:level", "key=value");
  expect_error([] { load_scene("builtin:sphere:level=1,level=2"); }, "'level'", "twice");
  expect_error([] { load_scene("builtin:sphere:level=x"); }, "level='x'", "integer");
  expect_error([] { load_scene(""); }, "empty scene spec", "");
  expect_error([] { load_scene("/no/such/dir/mesh.ply"); }, "mesh.ply", "no such file");
}

}  // namespace
}  // namespace rayaccel
