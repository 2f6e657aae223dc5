// Unit tests of Scene::from_buffers: triangles read in place from caller buffers (strides, uint16 and uint32
// indices), the same answers as an owned copy, the bad-geometry rules, buffers_changed(), and the errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/scene/scene.h"
#include "../float_specials.h"

namespace rayaccel {
namespace {

using test_values::kNaN;

/// A mesh stored the way a renderer might: vertices of 5 floats (x y z + a texture coordinate), triangles of
/// four uint16 (three indices and a material), so both strides differ from the packed ones.
struct InterleavedMesh {
  std::vector<float> vertices;
  std::vector<std::uint16_t> triangles;

  void add_vertex(Vec3 p) { vertices.insert(vertices.end(), {p.x, p.y, p.z, 0.5f, 0.5f}); }
  void add_triangle(std::uint16_t a, std::uint16_t b, std::uint16_t c) { triangles.insert(triangles.end(), {a, b, c, 7}); }
  MeshBuffers buffers() const {
    MeshBuffers b;
    b.vertices = vertices.data();
    b.vertex_count = vertices.size() / 5;
    b.vertex_stride = 5 * sizeof(float);
    b.indices = triangles.data();
    b.triangle_count = triangles.size() / 4;
    b.index_type = IndexType::uint16;
    b.triangle_stride = 4 * sizeof(std::uint16_t);
    return b;
  }
  TriangleMesh owned() const {
    TriangleMesh m;
    for (std::size_t i = 0; i < vertices.size(); i += 5) m.vertices.push_back({vertices[i], vertices[i + 1], vertices[i + 2]});
    for (std::size_t i = 0; i < triangles.size(); i += 4) m.triangles.push_back({triangles[i], triangles[i + 1], triangles[i + 2]});
    return m;
  }
};

/// A wavy grid of n x n quads, two triangles each.
InterleavedMesh wavy_grid(int n) {
  InterleavedMesh m;
  for (int y = 0; y <= n; ++y) {
    for (int x = 0; x <= n; ++x) m.add_vertex({x * 0.37f, std::sin(x * 0.9f) * std::cos(y * 0.7f), y * 0.41f});
  }
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const auto v = static_cast<std::uint16_t>(y * (n + 1) + x);
      m.add_triangle(v, static_cast<std::uint16_t>(v + 1), static_cast<std::uint16_t>(v + n + 2));
      m.add_triangle(v, static_cast<std::uint16_t>(v + n + 2), static_cast<std::uint16_t>(v + n + 1));
    }
  }
  return m;
}

std::vector<Ray> downward_rays(const AABB& box, int n) {
  std::vector<Ray> rays;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const float x = box.lo.x + (box.hi.x - box.lo.x) * (i + 0.3f) / n;
      const float z = box.lo.z + (box.hi.z - box.lo.z) * (j + 0.6f) / n;
      rays.push_back(Ray{{x, box.hi.y + 1.0f, z}, 0.0f, {0.01f * i, -1.0f, 0.02f * j}, 100.0f});
    }
  }
  return rays;
}

TEST(SceneBuffers, ReadsStridedUint16BuffersLikeAnOwnedCopy) {
  const InterleavedMesh mesh = wavy_grid(12);
  const Scene borrowed = Scene::from_buffers(mesh.buffers(), "grid");
  const Scene owned = Scene::from_mesh(mesh.owned());
  EXPECT_TRUE(borrowed.borrows_buffers());
  EXPECT_FALSE(owned.borrows_buffers());
  EXPECT_EQ(borrowed.name(), "grid");
  EXPECT_EQ(borrowed.kind(), PrimitiveKind::triangles);
  ASSERT_EQ(borrowed.primitive_count(), owned.primitive_count());
  EXPECT_EQ(borrowed.vertex_count(), owned.vertex_count());
  EXPECT_TRUE(borrowed.mesh().vertices.empty()) << "no copy of the caller's vertices";
  EXPECT_EQ(borrowed.bounds(), owned.bounds());
  for (std::uint32_t id = 0; id < owned.primitive_count(); ++id) {
    EXPECT_EQ(borrowed.triangle(id), owned.triangle(id));
    EXPECT_EQ(borrowed.primitive_bounds(id), owned.primitive_bounds(id));
  }
  EXPECT_LT(borrowed.memory_bytes(), owned.memory_bytes());
  for (const char* spec : {"brute_force", "bvh_wide", "kdtree"}) {
    SCOPED_TRACE(spec);
    auto a = make_accelerator(spec), b = make_accelerator(spec);
    a->build(borrowed);
    b->build(owned);
    int hits = 0;
    for (const Ray& ray : downward_rays(owned.bounds(), 16)) {
      const Hit x = a->intersect(ray), y = b->intersect(ray);
      EXPECT_EQ(x.t, y.t);
      EXPECT_EQ(x.prim_id, y.prim_id);
      EXPECT_EQ(a->occluded(ray), b->occluded(ray));
      hits += x.found() ? 1 : 0;
    }
    EXPECT_GT(hits, 200) << "the rays should mostly hit the grid";
  }
}

TEST(SceneBuffers, PackedUint32AndBadGeometryRules) {
  // 0 good, 1 NaN vertex, 2 collinear: as in from_mesh, the bad ones keep their ids, leave bounds, are never hit.
  const float vertices[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, kNaN, 0, 0, 2, 2, 2, 3, 3, 3};
  const std::uint32_t indices[] = {0, 1, 2, 3, 1, 2, 0, 4, 5};
  MeshBuffers b;
  b.vertices = vertices;
  b.vertex_count = 6;
  b.indices = indices;
  b.triangle_count = 3;
  const Scene s = Scene::from_buffers(b);
  EXPECT_EQ(s.primitive_count(), 3u);
  EXPECT_EQ(s.invalid_count(), 1u);
  EXPECT_EQ(s.degenerate_count(), 1u);
  EXPECT_EQ(s.bounds(), AABB(Vec3{0, 0, 0}, Vec3{1, 1, 0}));
  EXPECT_EQ(s.triangle(1), (std::array<Vec3, 3>{})) << "an excluded triangle reads as a point";
  const PreparedRay ray(Ray{{0.25f, 0.25f, -1.0f}, 0.0f, {0, 0, 1}, 10.0f});
  Hit hit = Hit::begin(ray);
  EXPECT_FALSE(s.intersect(1, ray, hit));
  EXPECT_FALSE(s.intersect(2, ray, hit));
  EXPECT_TRUE(s.intersect(0, ray, hit));
  EXPECT_EQ(hit.t, 1.0f);
}

TEST(SceneBuffers, BuffersChangedRereadsVerticesWrittenInPlace) {
  float vertices[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint16_t indices[] = {0, 1, 2};
  MeshBuffers b;
  b.vertices = vertices;
  b.vertex_count = 3;
  b.indices = indices;
  b.triangle_count = 1;
  b.index_type = IndexType::uint16;
  Scene s = Scene::from_buffers(b);
  auto accel = make_accelerator("bvh");
  accel->build(s);
  for (int v = 0; v < 3; ++v) vertices[3 * v + 2] = 4.0f;  // the triangle moves to z = 4
  s.buffers_changed();
  EXPECT_EQ(s.bounds(), AABB(Vec3{0, 0, 4}, Vec3{1, 1, 4}));
  accel->build(s);
  const Hit hit = accel->intersect(Ray{{0.2f, 0.2f, 0.0f}, 0.0f, {0, 0, 1}, 10.0f});
  EXPECT_EQ(hit.t, 4.0f);
  EXPECT_EQ(hit.prim_id, 0u);
  EXPECT_THROW(s.set_vertices(std::vector<Vec3>(3)), Error) << "the caller's buffers are written by the caller";
  EXPECT_THROW(s.append_triangles({}, {}), Error);
  EXPECT_THROW(Scene::from_mesh({}).buffers_changed(), Error) << "an owned mesh has no buffers";
}

TEST(SceneBuffers, BadBuffersAreErrorsThatSayWhy) {
  const float vertices[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint32_t indices[] = {0, 1, 2, 0, 2, 3};
  MeshBuffers b;
  b.vertices = vertices;
  b.vertex_count = 3;
  b.indices = indices;
  b.triangle_count = 2;
  const auto message = [](const MeshBuffers& buffers) -> std::string {
    try {
      Scene::from_buffers(buffers);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message(b).find("triangle 1 uses vertex index 3"), std::string::npos) << message(b);
  b.triangle_count = 1;
  EXPECT_EQ(message(b), "");
  MeshBuffers bad = b;
  bad.vertex_stride = 8;
  EXPECT_NE(message(bad).find("vertex_stride 8"), std::string::npos) << message(bad);
  bad = b;
  bad.triangle_stride = 10;
  EXPECT_NE(message(bad).find("triangle_stride 10"), std::string::npos) << message(bad);
  bad = b;
  bad.vertices = nullptr;
  EXPECT_NE(message(bad).find("vertices is null"), std::string::npos) << message(bad);
  bad = b;
  bad.indices = nullptr;
  EXPECT_NE(message(bad).find("indices is null"), std::string::npos) << message(bad);
  EXPECT_EQ(Scene::from_buffers(MeshBuffers{}).primitive_count(), 0u) << "empty buffers make an empty scene";
}

}  // namespace
}  // namespace rayaccel
