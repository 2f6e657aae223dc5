// Unit tests of Scene: invalid primitives (kept by id, excluded from bounds and builds, never hit), degenerate
// counts, spheres and user primitives, set_vertices and append_triangles, and the errors for bad indices.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "rayaccel/render/shading.h"
#include "rayaccel/core/error.h"
#include "rayaccel/scene/scene.h"
#include "../float_specials.h"

namespace rayaccel {
namespace {

using test_values::kInf;
using test_values::kNaN;

/// Triangles: 0 good, 1 NaN vertex, 2 collinear, 3 good, 4 infinite vertex, 5 a point.
TriangleMesh mixed_mesh() {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0},          // 0..2 good
                {kNaN, 0, 0},                             // 3
                {2, 2, 2}, {3, 3, 3},                     // 4, 5: collinear with 0
                {0, 0, 5}, {1, 0, 5}, {0, 1, 5},          // 6..8 good, at z = 5
                {0, kInf, 0},                             // 9
                {7, 7, 7}};                               // 10
  m.triangles = {{0, 1, 2}, {3, 1, 2}, {0, 4, 5}, {6, 7, 8}, {0, 9, 1}, {10, 10, 10}};
  return m;
}

TEST(Scene, InvalidPrimitivesKeepTheirIdButLeaveBoundsAndBuilds) {
  const Scene s = Scene::from_mesh(mixed_mesh(), "mixed");
  EXPECT_EQ(s.name(), "mixed");
  EXPECT_EQ(s.kind(), PrimitiveKind::triangles);
  EXPECT_EQ(s.primitive_count(), 6u);
  EXPECT_EQ(s.invalid_count(), 2u);
  EXPECT_FALSE(s.is_valid(1));
  EXPECT_FALSE(s.is_valid(4));
  EXPECT_TRUE(s.primitive_bounds(1).is_empty());
  // Degenerate triangles (2: collinear, 5: a point) leave bounds and builds too.
  EXPECT_EQ(s.bounds(), AABB(Vec3{0, 0, 0}, Vec3{1, 1, 5}));
  const PrimRefs refs = s.build_references();
  ASSERT_EQ(refs.size(), 2u);
  const std::uint32_t expected_ids[] = {0, 3};
  for (std::size_t i = 0; i < refs.size(); ++i) {
    EXPECT_EQ(refs[i].prim_id, expected_ids[i]);
    EXPECT_EQ(refs[i].bounds, s.primitive_bounds(refs[i].prim_id));
  }
  // The invalid triangle is never hit, even by a ray through where its finite vertices are.
  const PreparedRay ray(Ray{{0.25f, 0.25f, -1.0f}, -kInf, {0, 0, 1}, kInf});
  Hit hit = Hit::begin(ray);
  EXPECT_FALSE(s.intersect(1, ray, hit));
  EXPECT_FALSE(s.intersect(4, ray, hit));
  EXPECT_TRUE(s.intersect(0, ray, hit));
  EXPECT_EQ(hit.prim_id, 0u);
}

TEST(Scene, DegenerateTrianglesAreCountedAndExcludedFromBuilds) {
  const Scene s = Scene::from_mesh(mixed_mesh());
  EXPECT_EQ(s.degenerate_count(), 2u) << "the collinear triangle and the point; invalid ones are not counted";
  EXPECT_FALSE(s.is_valid(2));
  EXPECT_FALSE(s.is_valid(5));
  EXPECT_TRUE(s.primitive_bounds(5).is_empty()) << "a degenerate triangle has no box";
  EXPECT_EQ(s.valid_count() + s.invalid_count() + s.degenerate_count(), s.primitive_count());
  for (const PrimRef& r : s.build_references()) {
    EXPECT_NE(r.prim_id, 2u);
    EXPECT_NE(r.prim_id, 5u);
  }
  EXPECT_EQ(s.build_references().size(), s.valid_count());
}

TEST(Scene, ZeroAreaTrianglesAreNeverHit) {
  // scene.h: a zero-area (degenerate) triangle is never hit -- also when its three vertices are distinct but exactly
  // collinear, where the sheared float test alone could report one.
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 2, 3}, {2, 4, 6}, {0.5f, 0, 0}, {0.75f, 0, 0}, {1, 1, 1}};
  m.triangles = {{0, 1, 2}, {0, 3, 4}, {5, 5, 5}, {0, 1, 1}};
  const Scene s = Scene::from_mesh(m);
  ASSERT_EQ(s.degenerate_count(), 4u);
  int hits = 0;
  for (int i = 0; i < 400; ++i) {
    const std::uint32_t id = static_cast<std::uint32_t>(i) % 4;
    const auto& t = s.triangle(id);
    const float w = static_cast<float>(i) / 400.0f;
    const Vec3 target = t[0] * (1.0f - w) + t[1] * w;  // on the segment the triangle collapses to
    const Vec3 o = target + Vec3{std::sin(0.7f * static_cast<float>(i)), 0.5f, std::cos(1.3f * static_cast<float>(i))};
    const PreparedRay ray(Ray{o, -kInf, target - o, kInf});
    Hit hit = Hit::begin(ray);
    hits += s.intersect(id, ray, hit) ? 1 : 0;
  }
  EXPECT_EQ(hits, 0) << "rays aimed at zero-area triangles reported hits";
}

TEST(Scene, ThinTrianglesFarAcrossKeepTheirArea) {
  // The fuzz input of corpus thin-triangle-read-as-zero-area: two vertices 7.875 apart on the z axis and a third
  // at z = 3.8e24. Both edges from the far vertex round to the same vector in double (7.875 is below its ulp there),
  // so a cross product in double read zero area, and the triangle was dropped; exactly, its area is about
  // 7.875 * 1.25 / 2 (the far vertex is 1.25 from the z axis), and the ray through the short edge's middle hits it.
  TriangleMesh m;
  m.vertices = {{-0x1.a108d8p-57f, -1.25f, 0x1.c8fb98p+81f}, {0, 0, 7.875f}, {0, 0, 0}};
  m.triangles = {{0, 1, 2}};
  const Scene s = Scene::from_mesh(m);
  EXPECT_EQ(s.degenerate_count(), 0u);
  ASSERT_TRUE(s.is_valid(0));
  const PreparedRay ray(Ray{{7.5f, 7.5f, 7.5f}, 0.0f, {-7.5f, -7.5f, -3.5625f}, kInf});
  Hit hit = Hit::begin(ray);
  ASSERT_TRUE(s.intersect(0, ray, hit));
  EXPECT_EQ(hit.t, 1.0f) << "(7.5, 7.5, 7.5) + (-7.5, -7.5, -3.5625) = (0, 0, 3.9375), the short edge's middle";
}

TEST(Scene, OutOfRangeIndexIsAnError) {
  TriangleMesh m = mixed_mesh();
  m.triangles.push_back({0, 1, 11});
  try {
    (void)Scene::from_mesh(m);
    FAIL() << "expected Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("11"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("triangle 6"), std::string::npos) << e.what();
  }
}

TEST(Scene, SetVerticesRederivesEverything) {
  Scene s = Scene::from_mesh(mixed_mesh());
  std::vector<Vec3> v = s.mesh().vertices;
  v[3] = {0.5f, 0.5f, 1.0f};        // triangle 1 becomes valid
  v[7] = {kNaN, 0.0f, 5.0f};        // triangle 3 becomes invalid
  v[10] = {-1.0f, -1.0f, -1.0f};    // the point moves
  s.set_vertices(v);
  EXPECT_TRUE(s.is_valid(1));
  EXPECT_FALSE(s.is_valid(3));
  EXPECT_EQ(s.invalid_count(), 2u);
  EXPECT_EQ(s.triangle(1)[0], (Vec3{0.5f, 0.5f, 1.0f}));
  EXPECT_EQ(s.bounds(), AABB(Vec3{0, 0, 0}, Vec3{1, 1, 1})) << "the moved point is still degenerate";
  EXPECT_EQ(s.degenerate_count(), 2u);
  v.pop_back();
  EXPECT_THROW(s.set_vertices(v), Error) << "vertex count must not change";
  EXPECT_THROW(Scene::from_spheres({{{0, 0, 0}, 1.0f}}).set_vertices(v), Error) << "not a mesh";
}

TEST(Scene, AppendTrianglesAddsIdsAndBounds) {
  Scene s = Scene::from_mesh(mixed_mesh());
  const std::vector<Vec3> more{{10, 10, 10}, {11, 10, 10}, {10, 11, 10}};
  const std::vector<std::array<std::uint32_t, 3>> tris{{11, 12, 13}, {0, 11, 12}, {13, 13, 13}};
  EXPECT_EQ(s.append_triangles(more, tris), 6u);
  EXPECT_EQ(s.primitive_count(), 9u);
  EXPECT_EQ(s.triangle(6)[0], (Vec3{10, 10, 10}));
  EXPECT_EQ(s.bounds().hi, (Vec3{11, 11, 10}));
  EXPECT_EQ(s.degenerate_count(), 3u);
  EXPECT_EQ(s.build_references().size(), 4u) << "triangles 0, 3, 6, 7";
  // A bad index is reported and changes nothing.
  const std::vector<std::array<std::uint32_t, 3>> bad{{0, 1, 99}};
  EXPECT_THROW(s.append_triangles({}, bad), Error);
  EXPECT_EQ(s.primitive_count(), 9u);
  EXPECT_EQ(s.mesh().vertices.size(), 14u);
  EXPECT_THROW(Scene::from_spheres({}).append_triangles(more, tris), Error) << "not a mesh";
}

TEST(Scene, SpheresWithBadCenterOrRadiusAreInvalid) {
  const Scene s = Scene::from_spheres({{{0, 0, 0}, 1.0f},
                                       {{0, 0, 0}, 0.0f},
                                       {{0, 0, 0}, -1.0f},
                                       {{0, 0, 0}, kNaN},
                                       {{0, 0, 0}, kInf},
                                       {{kNaN, 0, 0}, 1.0f},
                                       {{4, 0, 0}, 0.5f}});
  EXPECT_EQ(s.kind(), PrimitiveKind::spheres);
  EXPECT_EQ(s.invalid_count(), 5u);
  EXPECT_EQ(s.degenerate_count(), 0u);
  EXPECT_EQ(s.build_references().size(), 2u);
  EXPECT_TRUE(s.primitive_bounds(0).contains(AABB(Vec3{-1.0f}, Vec3{1.0f})));
  EXPECT_TRUE(s.bounds().contains(Vec3{4.5f, 0.0f, 0.0f}));
  std::array<Vec3, 8> hull;
  EXPECT_EQ(s.hull_points(0, hull), 8);
  for (const Vec3& p : hull) EXPECT_TRUE(s.primitive_bounds(0).contains(p));
  const Ray ray{{-5, 0, 0}, 0.0f, {1, 0, 0}, kInf};
  const PreparedRay pr(ray);
  Hit hit = Hit::begin(pr);
  ASSERT_TRUE(s.intersect(0, pr, hit));
  EXPECT_FLOAT_EQ(hit.t, 4.0f);
  EXPECT_EQ(geometric_normal(s, ray, hit), (Vec3{-1, 0, 0}));
}

TEST(Scene, UserPrimitivesNeedCallbacksAndValidBounds) {
  UserPrimitives missing;
  missing.count = 2;
  EXPECT_THROW(Scene::from_user(missing), Error);
  EXPECT_NO_THROW(Scene::from_user(UserPrimitives{}));
  UserPrimitives prims;
  prims.count = 3;
  prims.bounds = [](std::uint32_t id) {
    if (id == 1) return AABB::empty();
    if (id == 2) return AABB(Vec3{0.0f}, Vec3{kInf});
    return AABB(Vec3{0.0f}, Vec3{1.0f});
  };
  prims.intersect = [](std::uint32_t, const PreparedRay&, Hit&) { return false; };
  const Scene s = Scene::from_user(prims);
  EXPECT_EQ(s.kind(), PrimitiveKind::user);
  EXPECT_EQ(s.invalid_count(), 2u);
  ASSERT_EQ(s.build_references().size(), 1u);
  EXPECT_EQ(s.build_references()[0].prim_id, 0u);
}

/// A strip of `n` triangles over shared vertices in which every seventh triangle is a point (degenerate) and every
/// thirteenth has a NaN vertex: invalid primitives spread over many of build_references()' blocks of ids.
TriangleMesh long_strip_with_holes(std::uint32_t n) {
  TriangleMesh m;
  for (std::uint32_t i = 0; i < n / 2 + 2; ++i) {
    m.vertices.push_back({static_cast<float>(i), 0.0f, 0.0f});
    m.vertices.push_back({static_cast<float>(i), 1.0f, 0.5f * static_cast<float>(i % 3)});
  }
  const auto nan_vertex = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.push_back({kNaN, 0.0f, 0.0f});
  for (std::uint32_t t = 0; t < n; ++t) {
    const std::uint32_t a = t, b = t + 1, c = t + 2;
    if (t % 7 == 3) {
      m.triangles.push_back({a, a, a});
    } else if (t % 13 == 5) {
      m.triangles.push_back({a, nan_vertex, c});
    } else {
      m.triangles.push_back({a, b, c});
    }
  }
  return m;
}

TEST(Scene, ReferencesOfManyBlocksComeInIdOrderWithTheirVerticesBounds) {
  const std::uint32_t n = 100003;  // several blocks of ids and a partial last one
  const Scene s = Scene::from_mesh(long_strip_with_holes(n));
  const PrimRefs refs = s.build_references(5);
  ASSERT_EQ(refs.size(), s.valid_count());
  EXPECT_GE(refs.capacity(), refs.size() + 5) << "the extra capacity asked for";
  std::size_t next = 0;
  for (std::uint32_t id = 0; id < n; ++id) {
    const bool expect_valid = id % 7 != 3 && id % 13 != 5;
    ASSERT_EQ(s.is_valid(id), expect_valid) << id;
    if (!expect_valid) continue;
    ASSERT_LT(next, refs.size());
    ASSERT_EQ(refs[next].prim_id, id);
    const auto [a, b, c] = s.triangle(id);
    ASSERT_EQ(refs[next].bounds, AABB::of_point(a).extend(b).extend(c)) << id;
    ++next;
  }
  EXPECT_EQ(next, refs.size());
}

TEST(Scene, HoldsTheMeshOnceAndAByteATriangle) {
  // No per-triangle vertex copy and no per-triangle boxes: the mesh's arrays and one validity byte a triangle.
  const TriangleMesh mesh = long_strip_with_holes(1000);
  const Scene s = Scene::from_mesh(mesh);
  EXPECT_EQ(s.memory_bytes(), mesh.vertices.size() * sizeof(Vec3) + mesh.triangles.size() * (3 * 4 + 1));
  const Scene spheres = Scene::from_spheres({{{0, 0, 0}, 1.0f}, {{2, 0, 0}, 1.0f}});
  EXPECT_EQ(spheres.memory_bytes(), 2 * (sizeof(Sphere) + sizeof(AABB) + 1));
}

TEST(Scene, TriangleNormalAndHullPoints) {
  const Scene s = Scene::from_mesh(mixed_mesh());
  const Ray ray{{0.2f, 0.2f, 1.0f}, 0.0f, {0, 0, -1}, kInf};
  Hit hit;
  hit.prim_id = 0;
  hit.t = 1.0f;
  EXPECT_EQ(geometric_normal(s, ray, hit), (Vec3{0, 0, 1}));
  std::array<Vec3, 8> hull;
  ASSERT_EQ(s.hull_points(3, hull), 3);
  EXPECT_EQ(hull[1], (Vec3{1, 0, 5}));
  EXPECT_STREQ(to_string(PrimitiveKind::spheres), "spheres");
  EXPECT_EQ(Scene::from_mesh({}).bounds(), AABB::empty());
}

}  // namespace
}  // namespace rayaccel
