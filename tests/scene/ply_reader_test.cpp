// Unit tests of the PLY reader (scene/ply_reader.h): every type and byte order, fan triangulation, and the
// malformed files of issue #19 (a header cut short, fewer elements than declared, a face line swallowing the next, a
// list count too large for its type, truncated binary data, absurd counts), each an error naming file, place and
// value. Plus: the shared bunny loads exactly as assimp loads it.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#ifdef RAYACCEL_TEST_WITH_ASSIMP
#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#endif

#include "../shared_scenes.h"
#include "rayaccel/core/error.h"
#include "rayaccel/double/double_scene.h"
#include "rayaccel/scene/import.h"
#include "rayaccel/scene/ply_reader.h"
#include "temp_dir.h"

namespace rayaccel {
namespace {

using testing::TempDir;

TriangleMesh parse(const std::string& text) { return parse_ply(std::as_bytes(std::span(text.data(), text.size())), "t.ply"); }

/// parse(text) must throw an Error whose message holds every one of `parts`.
void expect_error(const std::string& text, const std::vector<std::string>& parts) {
  try {
    parse(text);
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const Error& e) {
    for (const std::string& part : parts) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << "'" << part << "' not in: " << e.what();
    }
  }
}

const std::string kAsciiHeader =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
const std::string kAsciiVertices = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";

TEST(PlyReader, AsciiFacesAreFanTriangulatedInOrder) {
  const TriangleMesh mesh = parse(kAsciiHeader + kAsciiVertices + "4 0 1 2 3\n3 3 2 1\n");
  ASSERT_EQ(mesh.vertices.size(), 4u);
  ASSERT_EQ(mesh.triangles.size(), 3u);
  EXPECT_EQ(mesh.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_EQ(mesh.triangles[2], (std::array<std::uint32_t, 3>{3, 2, 1}));
  EXPECT_EQ(mesh.vertices[2], (Vec3{1.0f, 1.0f, 0.0f}));
}

/// Appends `value` as `size` bytes in big-endian order.
template <class T>
void put_big_endian(std::string& out, T value) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::little) std::reverse(b, b + sizeof(T));
  out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

TEST(PlyReader, BinaryBigEndianWithOtherTypesAndExtraProperties) {
  std::string file =
      "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\nproperty uchar red\n"
      "property short y\nproperty float z\nelement material 1\nproperty list int float weights\n"
      "element face 1\nproperty uchar flags\nproperty list ushort uint vertex_indices\nend_header\n";
  const double xs[3] = {0.5, 1.25, -3.0};
  const std::int16_t ys[3] = {0, -2, 7};
  const float zs[3] = {1.0f, 2.0f, 3.0f};
  for (int i = 0; i < 3; ++i) {
    put_big_endian(file, xs[i]);
    put_big_endian(file, std::uint8_t(200));
    put_big_endian(file, ys[i]);
    put_big_endian(file, zs[i]);
  }
  put_big_endian(file, std::int32_t(2));
  put_big_endian(file, 1.0f);
  put_big_endian(file, 2.0f);
  put_big_endian(file, std::uint8_t(9));
  put_big_endian(file, std::uint16_t(3));
  for (std::uint32_t i : {2u, 0u, 1u}) put_big_endian(file, i);
  const TriangleMesh mesh = parse(file);
  ASSERT_EQ(mesh.vertices.size(), 3u);
  EXPECT_EQ(mesh.vertices[1], (Vec3{1.25f, -2.0f, 2.0f}));
  EXPECT_EQ(mesh.vertices[2], (Vec3{-3.0f, 7.0f, 3.0f}));
  ASSERT_EQ(mesh.triangles.size(), 1u);
  EXPECT_EQ(mesh.triangles[0], (std::array<std::uint32_t, 3>{2, 0, 1}));
  // Cut anywhere inside the data, it is an error naming the file (a count the rest cannot hold, or where it ends).
  expect_error(file.substr(0, file.size() - 1), {"t.ply", "face 0 (byte", "ends before face 0 property 'vertex_indices' item 2"});
  for (std::size_t cut = file.size() - 2; cut > file.find("end_header\n") + 11; cut -= 3) {
    expect_error(file.substr(0, cut), {"t.ply"});
  }
}

TriangleMeshD parse_double(const std::string& text) {
  return parse_ply_double(std::as_bytes(std::span(text.data(), text.size())), "t.ply");
}

TEST(PlyReader, DoubleReadKeepsDoublePropertiesAsRead) {
  // Coordinates near 1e7 with fractions float cannot hold (its ulp there is 1): binary big-endian and ASCII.
  const double xs[3] = {1e7 + 0.1, 1e7 + 0.5 + 0x1p-28, -1e7 - 1.0 / 3.0};
  std::string binary =
      "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < 3; ++i) {
    put_big_endian(binary, xs[i]);
    put_big_endian(binary, -xs[i]);
    put_big_endian(binary, 0.1f);
  }
  put_big_endian(binary, std::uint8_t(3));
  for (std::int32_t i : {0, 1, 2}) put_big_endian(binary, i);
  const TriangleMeshD mesh = parse_double(binary);
  ASSERT_EQ(mesh.vertices.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(mesh.vertices[i], (DVec3{xs[i], -xs[i], double(0.1f)})) << "vertex " << i;
  }
  ASSERT_EQ(mesh.triangles.size(), 1u);
  // The float read of the same file rounds each coordinate to float, once.
  const TriangleMesh rounded = parse(binary);
  EXPECT_EQ(rounded.vertices[0], (Vec3{float(xs[0]), float(-xs[0]), 0.1f}));
  EXPECT_NE(double(rounded.vertices[0].x), xs[0]);

  const std::string ascii =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "10000000.123456789 -0.3 0.1\n1e7 2 3\n-10000000.5 0 1\n3 0 1 2\n";
  const TriangleMeshD text_mesh = parse_double(ascii);
  ASSERT_EQ(text_mesh.vertices.size(), 3u);
  EXPECT_EQ(text_mesh.vertices[0], (DVec3{10000000.123456789, -0.3, double(0.1f)}));
  EXPECT_EQ(text_mesh.vertices[2], (DVec3{-10000000.5, 0.0, 1.0}));
}

TEST(PlyReader, DoubleReadChecksAsTheFloatReadDoes) {
  const std::string bad_index = kAsciiHeader + kAsciiVertices + "3 0 1 2\n3 0 2 4\n";
  for (const auto& read : {std::function<void()>([&] { parse(bad_index); }),
                           std::function<void()>([&] { parse_double(bad_index); })}) {
    try {
      read();
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("t.ply"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("face 1 uses vertex index 4"), std::string::npos) << e.what();
    }
  }
}

TEST(PlyReader, HeaderCutShortIsAnErrorNotAHang) {
  expect_error("ply\nformat ascii 1.0\n", {"t.ply", "ends inside its header"});
  expect_error("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x", {"ends inside its header"});
  expect_error("", {"empty file"});
  expect_error("ply", {"ends inside its header"});
  expect_error("plyx\nformat ascii 1.0\nend_header\n", {"not a PLY file"});
  expect_error("ply\nformat ascii 2.0\nend_header\n", {"header line 2", "version '2.0'"});
  expect_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n", {"header line 4", "'quad'"});
  expect_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n", {"lacks x, y or z"});
}

TEST(PlyReader, FewerElementsThanDeclaredAreErrors) {
  expect_error(kAsciiHeader + "0.0 0.0 0.0\n1.0 0.0 0.0\n1.0 1.0 0.0\n", {"t.ply", "ends after 3 of the 4 vertex elements"});
  // Too few bytes left for the count at all: said before anything is read.
  expect_error(kAsciiHeader + "0 0 0\n1 0 0\n1 1 0\n", {"t.ply", "count 4 needs at least 6 bytes each"});
  expect_error(kAsciiHeader + kAsciiVertices + "3 0 1 2\n", {"t.ply", "ends after 1 of the 2 face elements"});
}

TEST(PlyReader, FaceLineSwallowingTheNextIsAnError) {
  // The first face declares 4 indices but holds 3; the second line must not be read as its fourth.
  expect_error(kAsciiHeader + kAsciiVertices + "4 0 1 2\n3 3 2 1\n",
               {"line 14", "line ends before face 0 property 'vertex_indices' item 3"});
  expect_error(kAsciiHeader + kAsciiVertices + "3 0 1 2 3\n3 3 2 1\n", {"line 14", "1 more values"});
  expect_error(kAsciiHeader + "0 0 0 7\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 1 2\n", {"line 10", "more values"});
}

TEST(PlyReader, ValuesMustFitTheirTypes) {
  std::string big_face = "300";
  for (int i = 0; i < 300; ++i) big_face += " " + std::to_string(i % 4);
  expect_error(kAsciiHeader + kAsciiVertices + big_face + "\n3 0 1 2\n", {"line 14", "count '300' does not fit type uchar"});
  expect_error(kAsciiHeader + kAsciiVertices + "3 0 1 2\n3 0 1 x\n", {"line 15", "'x' is not a number of type int"});
  expect_error(kAsciiHeader + kAsciiVertices + "3 0 1 2\n3 0 1 1.5\n", {"line 15", "'1.5'"});
  expect_error(kAsciiHeader + "0 0 zero\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 1 2\n", {"line 10", "'zero'"});
  expect_error(kAsciiHeader + kAsciiVertices + "3 0 1 2\n3 0 1 4\n", {"face 1 uses vertex index 4, out of range"});
  expect_error(kAsciiHeader + kAsciiVertices + "3 0 1 2\n3 0 -1 2\n", {"vertex index -1, out of range"});
  expect_error(kAsciiHeader + kAsciiVertices + "3 0 1 2\n3 0 1 2\n5 5 5\n", {"line 16", "data after the last element"});
}

TEST(PlyReader, AbsurdCountsNameTheCountBeforeAllocating) {
  expect_error("ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
               "property float z\nend_header\n\1\2\3",
               {"t.ply", "header line 3", "count 4000000000", "bytes of data are left"});
  expect_error("ply\nformat ascii 1.0\nelement vertex 18446744073709551615\nproperty float x\nproperty float y\n"
               "property float z\nend_header\n1 2 3\n",
               {"count 18446744073709551615"});
  expect_error("ply\nformat ascii 1.0\nelement vertex 99999999999999999999\nend_header\n",
               {"header line 3", "is not a non-negative integer"});
  expect_error("ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
               "property float z\nelement face 5\nend_header\n",
               {"element 'face' has no properties but a count of 5"});
}

TEST(PlyReader, ImportMeshUsesItForPlyByContent) {
  TempDir dir;
  // A header cut short, under a name assimp would also try: an error naming the file, promptly.
  const auto cut = dir.write("cut.mesh", "ply\nformat ascii 1.0\n");
  try {
    import_mesh(cut);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cut.mesh"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("ends inside its header"), std::string::npos) << e.what();
  }
  const auto file = dir.write("quad.ply", kAsciiHeader + kAsciiVertices + "4 0 1 2 3\n3 3 2 1\n");
  EXPECT_EQ(import_mesh(file).triangles.size(), 3u);
}

#ifdef RAYACCEL_TEST_WITH_ASSIMP
/// Every triangle's corners as assimp reads the file (no post-processing, one mesh, the previous import path).
std::vector<std::array<Vec3, 3>> assimp_triangles(const std::filesystem::path& path) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path.string(), 0);
  std::vector<std::array<Vec3, 3>> out;
  if (!scene) return out;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh& mesh = *scene->mMeshes[m];
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      const auto at = [&](unsigned k) {
        const aiVector3D& v = mesh.mVertices[face.mIndices[k]];
        return Vec3{v.x, v.y, v.z};
      };
      for (unsigned k = 1; k + 1 < face.mNumIndices; ++k) out.push_back({at(0), at(k), at(k + 1)});
    }
  }
  return out;
}

TEST(PlyReader, SharedBunnyLoadsExactlyAsAssimpLoadsIt) {
  const auto file = testing::shared_scenes_dir() / "bunny.ply";
  RAYACCEL_NEED_SHARED_FILE(file);
  const TriangleMesh ours = import_mesh(file);
  const auto theirs = assimp_triangles(file);
  ASSERT_EQ(ours.triangles.size(), theirs.size());
  std::size_t differ = 0;
  for (std::size_t t = 0; t < theirs.size(); ++t) {
    const auto& tri = ours.triangles[t];
    const std::array<Vec3, 3> corners{ours.vertices[tri[0]], ours.vertices[tri[1]], ours.vertices[tri[2]]};
    if (std::memcmp(&corners, &theirs[t], sizeof(corners)) != 0 && differ++ < 3) {
      ADD_FAILURE() << "triangle " << t << " differs";
    }
  }
  EXPECT_EQ(differ, 0u);
}
#endif

}  // namespace
}  // namespace rayaccel
