// Unit tests of the built-in procedural scenes: sizes, kinds, determinism, closed and consistently wound surfaces,
// and parameter validation.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <string>
#include <utility>

#include "rayaccel/core/error.h"
#include "rayaccel/scene/builtin_scenes.h"

namespace rayaccel {
namespace {

/// Empty when triangles [first, last) form a closed, consistently wound surface: every directed edge appears once
/// and its reverse once (so every edge is shared by exactly two triangles of opposite traversal).
std::string closed_surface_fault(const TriangleMesh& mesh, std::size_t first, std::size_t last) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (std::size_t i = first; i < last; ++i) {
    const auto& t = mesh.triangles[i];
    for (int k = 0; k < 3; ++k) {
      if (++directed[{t[k], t[(k + 1) % 3]}] > 1) {
        return "directed edge " + std::to_string(t[k]) + "->" + std::to_string(t[(k + 1) % 3]) + " used twice";
      }
    }
  }
  for (const auto& [edge, count] : directed) {
    if (!directed.count({edge.second, edge.first})) {
      return "edge " + std::to_string(edge.first) + "-" + std::to_string(edge.second) + " has one triangle";
    }
  }
  return "";
}

/// Signed volume enclosed by triangles [first, last) (positive for outward winding).
double signed_volume(const TriangleMesh& mesh, std::size_t first, std::size_t last) {
  double volume = 0.0;
  for (std::size_t i = first; i < last; ++i) {
    const auto& t = mesh.triangles[i];
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    volume += dot(a, cross(b, c)) / 6.0;
  }
  return volume;
}

TEST(BuiltinScenes, EveryDefaultSceneGeneratesAModestValidScene) {
  ASSERT_GE(builtin_scenes().size(), 8u);
  for (const auto& info : builtin_scenes()) {
    SCOPED_TRACE(info.name);
    const Scene scene = make_builtin_scene(info.name);
    EXPECT_EQ(scene.name(), info.name);
    EXPECT_EQ(scene.kind(), info.name == "sphereflake" ? PrimitiveKind::spheres : PrimitiveKind::triangles);
    EXPECT_GE(scene.primitive_count(), 1000u);
    EXPECT_LE(scene.primitive_count(), 50000u);
    EXPECT_EQ(scene.invalid_count(), 0u);
    EXPECT_FALSE(scene.bounds().is_empty());
    EXPECT_TRUE(scene.bounds().is_finite());
    EXPECT_GT(scene.bounds().volume(), 0.0f);
    EXPECT_FALSE(info.description.empty());
  }
}

TEST(BuiltinScenes, AreDeterministic) {
  for (const auto& info : builtin_scenes()) {
    SCOPED_TRACE(info.name);
    const Scene a = make_builtin_scene(info.name);
    const Scene b = make_builtin_scene(info.name);
    ASSERT_EQ(a.primitive_count(), b.primitive_count());
    EXPECT_EQ(a.mesh().vertices, b.mesh().vertices);
    EXPECT_EQ(a.mesh().triangles, b.mesh().triangles);
    ASSERT_EQ(a.spheres().size(), b.spheres().size());
    for (std::size_t i = 0; i < a.spheres().size(); ++i) {
      EXPECT_EQ(a.spheres()[i].center, b.spheres()[i].center);
      EXPECT_EQ(a.spheres()[i].radius, b.spheres()[i].radius);
    }
  }
}

TEST(BuiltinScenes, SeedsChangeRandomScenes) {
  for (const char* name : {"mountain", "soup", "slivers", "default"}) {
    SCOPED_TRACE(name);
    const Scene a = make_builtin_scene(name, {{"seed", "1"}});
    const Scene b = make_builtin_scene(name, {{"seed", "2"}});
    EXPECT_NE(a.mesh().vertices, b.mesh().vertices);
  }
}

TEST(BuiltinScenes, SizeParametersGiveTheDocumentedCounts) {
  EXPECT_EQ(make_builtin_scene("sphereflake", {{"level", "0"}}).primitive_count(), 1u);
  EXPECT_EQ(make_builtin_scene("sphereflake", {{"level", "2"}}).primitive_count(), 91u);
  EXPECT_EQ(make_builtin_scene("mountain", {{"level", "3"}}).primitive_count(), 128u);
  EXPECT_EQ(make_builtin_scene("sierpinski", {{"level", "2"}}).primitive_count(), 64u);
  EXPECT_EQ(make_builtin_scene("sphere", {{"level", "2"}}).primitive_count(), 320u);
  EXPECT_EQ(make_builtin_scene("soup", {{"count", "7"}}).primitive_count(), 7u);
  EXPECT_EQ(make_builtin_scene("slivers", {{"count", "5"}}).primitive_count(), 5u);
  EXPECT_EQ(make_builtin_scene("teapot_stadium", {{"segments", "10"}, {"tube", "4"}}).primitive_count(), 80u + 1568u);
  EXPECT_EQ(make_builtin_scene("default").primitive_count(), 13568u);
  EXPECT_EQ(make_builtin_scene("soup", {{"count", "0"}}).primitive_count(), 0u);
}

TEST(BuiltinScenes, SphereIsWatertightWithOutwardWinding) {
  for (const char* level : {"0", "1", "3"}) {
    SCOPED_TRACE(level);
    const Scene scene = make_builtin_scene("sphere", {{"level", level}, {"radius", "2"}});
    const TriangleMesh& mesh = scene.mesh();
    EXPECT_EQ(closed_surface_fault(mesh, 0, mesh.triangles.size()), "");
    // Euler characteristic of a sphere: V - E + F = 2, with E = 3F/2 for a closed triangle mesh.
    EXPECT_EQ(2 * mesh.vertices.size(), 4 + mesh.triangles.size());
    for (const Vec3& v : mesh.vertices) EXPECT_NEAR(length(v), 2.0f, 1e-5f);
    const double volume = signed_volume(mesh, 0, mesh.triangles.size());
    EXPECT_GT(volume, 0.0);
    EXPECT_LT(volume, 4.0 / 3.0 * std::numbers::pi * 8.0);
    EXPECT_EQ(scene.degenerate_count(), 0u);
  }
}

TEST(BuiltinScenes, TorusKnotOfTheStadiumIsClosedAndOutward) {
  const Scene scene = make_builtin_scene("teapot_stadium", {{"segments", "64"}, {"tube", "6"}});
  const std::size_t knot = 2 * 64 * 6;  // the knot's triangles come first
  EXPECT_EQ(closed_surface_fault(scene.mesh(), 0, knot), "");
  EXPECT_GT(signed_volume(scene.mesh(), 0, knot), 0.0);
  // Teapot in a stadium: the stadium dwarfs the object.
  AABB object;
  for (std::size_t i = 0; i < knot; ++i) object.extend(scene.primitive_bounds(static_cast<std::uint32_t>(i)));
  EXPECT_GT(scene.bounds().extent().x, 300.0f * object.extent().x);
  EXPECT_GE(object.lo.y, -1e-5f);  // resting on the field, not through it
}

TEST(BuiltinScenes, SierpinskiTetrahedraAreClosedWithTheExpectedVolume) {
  const Scene scene = make_builtin_scene("sierpinski", {{"level", "3"}, {"edge", "2"}});
  const TriangleMesh& mesh = scene.mesh();
  for (std::size_t t = 0; t < mesh.triangles.size(); t += 4) {
    ASSERT_EQ(closed_surface_fault(mesh, t, t + 4), "") << "tetrahedron " << t / 4;
  }
  // Each level keeps 4 copies of half the size: the volume halves.
  const double full = std::pow(2.0, 3.0) / (6.0 * std::numbers::sqrt2);
  EXPECT_NEAR(signed_volume(mesh, 0, mesh.triangles.size()), full / 8.0, 1e-5);
  EXPECT_FLOAT_EQ(scene.bounds().lo.y, 0.0f);
}

TEST(BuiltinScenes, MountainIsAHeightFieldFacingUp) {
  const Scene scene = make_builtin_scene("mountain", {{"level", "4"}, {"size", "10"}});
  for (std::uint32_t i = 0; i < scene.primitive_count(); ++i) {
    const auto& t = scene.triangle(i);
    EXPECT_GT(cross(t[1] - t[0], t[2] - t[0]).y, 0.0f) << "triangle " << i;
  }
  EXPECT_FLOAT_EQ(scene.bounds().lo.x, -5.0f);
  EXPECT_FLOAT_EQ(scene.bounds().hi.z, 5.0f);
  EXPECT_GT(scene.bounds().extent().y, 0.0f);
}

TEST(BuiltinScenes, SliversAreLongAndThin) {
  const Scene scene = make_builtin_scene("slivers", {{"count", "100"}, {"aspect", "500"}});
  for (std::uint32_t i = 0; i < scene.primitive_count(); ++i) {
    const auto& t = scene.triangle(i);
    const float base = length(t[1] - t[0]);
    const float height = length(cross(t[1] - t[0], t[2] - t[0])) / base;
    EXPECT_NEAR(base, 2.0f, 1e-5f);
    EXPECT_NEAR(height, 2.0f / 500.0f, 1e-5f);
  }
}

TEST(BuiltinScenes, SphereflakeChildrenTouchTheirParent) {
  const Scene scene = make_builtin_scene("sphereflake", {{"level", "1"}, {"radius", "3"}});
  const auto& s = scene.spheres();
  ASSERT_EQ(s.size(), 10u);
  for (std::size_t i = 1; i < s.size(); ++i) {
    EXPECT_FLOAT_EQ(s[i].radius, 1.0f);
    EXPECT_NEAR(length(s[i].center - s[0].center), 4.0f, 1e-5f);
  }
}

TEST(BuiltinScenes, UnknownNamesAndKeysListTheKnownOnes) {
  try {
    make_builtin_scene("teapot");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'teapot'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("sphereflake"), std::string::npos) << e.what();
  }
  try {
    make_builtin_scene("mountain", {{"levels", "3"}});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'levels'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("roughness"), std::string::npos) << e.what();
  }
}

TEST(BuiltinScenes, BadValuesAreNamed) {
  const std::vector<std::pair<std::string, std::map<std::string, std::string>>> bad = {
      {"mountain", {{"level", "abc"}}},     {"mountain", {{"level", "12"}}},   {"mountain", {{"level", "2.5"}}},
      {"mountain", {{"level", ""}}},        {"sphere", {{"radius", "-1"}}},    {"sphere", {{"radius", "nan"}}},
      {"soup", {{"size", "inf"}}},          {"soup", {{"seed", "-3"}}},        {"slivers", {{"count", "1e3"}}},
      {"teapot_stadium", {{"segments", "1048576"}, {"tube", "1024"}}},
  };
  for (const auto& [name, params] : bad) {
    const std::string value = params.begin()->second;
    SCOPED_TRACE(name + " " + params.begin()->first + "=" + value);
    try {
      make_builtin_scene(name, params);
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(value), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace rayaccel
