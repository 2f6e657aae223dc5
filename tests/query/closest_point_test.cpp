// Closest points: Ericson's point-triangle kernel against an independent reference (projection onto the plane when
// it falls inside, else the nearest of the three edges as segments), and every structure that answers queries against
// brute force (the same distance bit for bit) on random points, points on faces and points at vertices.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "../conformance/test_scenes.h"
#include "../shared_scenes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/geometry/point_triangle.h"
#include "rayaccel/scene/import.h"
#include "query_structures.h"
#include "voxel_shape.h"

namespace rayaccel {
namespace {

using conformance::Rng;
using testing::query_structures;

struct D3 {
  double x, y, z;
};
D3 to_d3(const Vec3& v) { return {v.x, v.y, v.z}; }
D3 operator-(const D3& a, const D3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator+(const D3& a, const D3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator*(const D3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(const D3& a, const D3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

/// Squared distance from p to the triangle by another route: the plane projection when inside (signs of the three
/// edge cross products against the normal), else the nearest point of the three edges (clamped segment projection).
double reference_distance_squared(const Vec3& pf, const Vec3& af, const Vec3& bf, const Vec3& cf) {
  const D3 p = to_d3(pf), a = to_d3(af), b = to_d3(bf), c = to_d3(cf);
  const D3 n = cross(b - a, c - a);
  const double nn = dot(n, n);
  const D3 q = p - n * (dot(p - a, n) / nn);
  if (dot(cross(b - a, q - a), n) >= 0 && dot(cross(c - b, q - b), n) >= 0 && dot(cross(a - c, q - c), n) >= 0) {
    const D3 g = p - q;
    return dot(g, g);
  }
  double best = INFINITY;
  for (const auto& [s, e] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
    const D3 d = e - s;
    double t = dot(p - s, d) / dot(d, d);
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    const D3 g = p - (s + d * t);
    best = std::min(best, dot(g, g));
  }
  return best;
}

TEST(PointTriangle, MatchesTheProjectionReferenceInEveryRegion) {
  Rng rng(5);
  for (int i = 0; i < 20000; ++i) {
    const AABB box{{-1, -1, -1}, {1, 1, 1}};
    const Vec3 a = rng.in_box(box), b = rng.in_box(box), c = rng.in_box(box);
    const Vec3 p = rng.in_box(AABB{{-3, -3, -3}, {3, 3, 3}});
    if (length(cross(b - a, c - a)) < 1e-3f) continue;
    const TrianglePoint t = closest_point_on_triangle(p, a, b, c);
    const double reference = reference_distance_squared(p, a, b, c);
    // Both are double computations of the same quantity from float inputs of magnitude <= 3: they agree to a few
    // double ulps of the squared scale (36).
    ASSERT_NEAR(t.distance_squared, reference, 1e-12) << i;
    // The point is the one its barycentrics name, inside the triangle.
    EXPECT_GE(t.u, 0.0);
    EXPECT_GE(t.v, 0.0);
    EXPECT_LE(t.u + t.v, 1.0 + 1e-12);
    const D3 q = to_d3(a) * (1 - t.u - t.v) + to_d3(b) * t.u + to_d3(c) * t.v;
    EXPECT_NEAR(q.x, t.x, 1e-12);
    EXPECT_NEAR(q.y, t.y, 1e-12);
    EXPECT_NEAR(q.z, t.z, 1e-12);
  }
}

TEST(PointTriangle, VerticesAndEdgePointsAreAtDistanceZero) {
  const Vec3 a{0.25f, 1, -2}, b{3, 0.5f, 1}, c{-1, 2, 0.75f};
  for (const Vec3& p : {a, b, c}) EXPECT_EQ(closest_point_on_triangle(p, a, b, c).distance_squared, 0.0);
  EXPECT_EQ(closest_point_on_triangle(b, a, b, c).u, 1.0);
  EXPECT_EQ(closest_point_on_triangle(c, a, b, c).v, 1.0);
  const Vec3 p{1, 1, 1}, q{3, 1, 1}, r{1, 3, 1};
  EXPECT_EQ(closest_point_on_triangle({2, 1, 1}, p, q, r).distance_squared, 0.0);  // an edge midpoint
  EXPECT_EQ(closest_point_on_triangle({2, 2, 5}, p, q, r).distance_squared, 16.0);  // above the hypotenuse
  EXPECT_EQ(closest_point_on_triangle({0, 0, 1}, p, q, r).distance_squared, 2.0);   // the vertex region of p
}

/// Random points about the scene, every vertex, and points on triangles (barycentric combinations rounded to float).
std::vector<Vec3> query_points(const Scene& scene, std::size_t random_count, std::size_t surface_count,
                               std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Vec3> points;
  const AABB& b = scene.bounds();
  const Vec3 margin = b.extent() * 0.5f;
  for (std::size_t i = 0; i < random_count; ++i) points.push_back(rng.in_box(AABB{b.lo - margin, b.hi + margin}));
  for (std::size_t i = 0; i < surface_count; ++i) {
    const auto t = scene.triangle(rng.below(scene.primitive_count()));
    const float u = rng.uniform(), v = rng.uniform() * (1 - u);
    points.push_back(t[0] * (1 - u - v) + t[1] * u + t[2] * v);
    points.push_back(t[i % 3]);
  }
  return points;
}

void expect_like_brute_force(const Scene& scene, const std::vector<Vec3>& points, float max_distance,
                             std::size_t structure_stride = 1) {
  const auto structures = query_structures(scene);
  ASSERT_EQ(structures[0]->spec(), "brute_force");
  std::vector<ClosestPoint> expected(points.size()), got(points.size());
  structures[0]->closest_points(points, expected, max_distance);
  for (std::size_t s = 1; s < structures.size(); s += structure_stride) {
    const Accelerator& accel = *structures[s];
    accel.closest_points(points, got, max_distance);
    for (std::size_t i = 0; i < points.size(); ++i) {
      ASSERT_EQ(got[i].found(), expected[i].found()) << accel.spec() << " point " << i;
      if (!got[i].found()) continue;
      ASSERT_EQ(got[i].distance, expected[i].distance) << accel.spec() << " point " << i;
      // Of equidistant triangles any may be named: its own distance is then the same.
      const auto t = scene.triangle(got[i].prim_id);
      const TrianglePoint own = closest_point_on_triangle(points[i], t[0], t[1], t[2]);
      EXPECT_EQ(float(std::sqrt(own.distance_squared)), got[i].distance) << accel.spec() << " point " << i;
      if (got[i].prim_id == expected[i].prim_id) {
        EXPECT_EQ(got[i].point, expected[i].point);
        EXPECT_EQ(got[i].u, expected[i].u);
        EXPECT_EQ(got[i].v, expected[i].v);
      }
    }
  }
}

TEST(ClosestPoint, EveryStructureAgreesWithBruteForceOnTheVoxelSolid) {
  const Scene scene = Scene::from_mesh(testing::voxel_shape_mesh(), "voxels");
  const auto points = query_points(scene, 1500, 300, 3);
  expect_like_brute_force(scene, points, std::numeric_limits<float>::infinity());
  expect_like_brute_force(scene, points, 0.25f);  // a search radius: far points find nothing
}

TEST(ClosestPoint, EveryStructureAgreesWithBruteForceOnASoup) {
  const Scene scene = Scene::from_mesh(conformance::random_soup_mesh(1500, 0.2f, 9), "soup");
  expect_like_brute_force(scene, query_points(scene, 1000, 200, 4), std::numeric_limits<float>::infinity());
}

TEST(ClosestPoint, VerticesAreAtDistanceZeroAndFacePointsOnTheirFace) {
  const Scene scene = Scene::from_mesh(testing::voxel_shape_mesh(), "voxels");
  auto accel = make_accelerator("bvh_wide");
  accel->build(scene);
  for (const Vec3& v : scene.mesh().vertices) {
    const ClosestPoint c = accel->closest_point(v);
    ASSERT_TRUE(c.found());
    EXPECT_EQ(c.distance, 0.0f);
    EXPECT_EQ(c.point, v);
  }
  // Face centres one unit above the floor of the solid (z = 0, facing -z) are at distance 1 below it.
  for (float x : {0.5f, 1.5f, 2.5f}) {
    const ClosestPoint c = accel->closest_point({x, 0.5f, -1.0f});
    EXPECT_EQ(c.distance, 1.0f);
    EXPECT_EQ(c.point, (Vec3{x, 0.5f, 0.0f}));
  }
}

TEST(ClosestPoint, BadQueriesAreRefusedNamingTheValue) {
  const Scene scene = Scene::from_mesh(testing::voxel_shape_mesh(), "voxels");
  auto accel = make_accelerator("bvh");
  accel->build(scene);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(accel->closest_point({nan, 0, 0}), Error);
  EXPECT_THROW(accel->closest_point({0, 0, 0}, -1.0f), Error);
  EXPECT_THROW(accel->closest_point({0, 0, 0}, nan), Error);
  std::vector<Vec3> points = {{0, 0, 0}, {1, std::numeric_limits<float>::infinity(), 0}};
  std::vector<ClosestPoint> out(2);
  try {
    accel->closest_points(points, out);
    ADD_FAILURE() << "a non-finite point was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("point 1"), std::string::npos) << e.what();
  }
}

TEST(ClosestPoint, SharedBunnyMatchesBruteForce) {
  const auto path = testing::shared_scenes_dir() / "bunny.ply";
  RAYACCEL_NEED_SHARED_FILE(path);
  const Scene scene = load_scene(path.string());
  const std::vector<std::string> specs = {"bvh", "bvh:bv=obb,builder=ploc", "bvh:builder=sbvh", "bvh_wide",
                                          "bvh_wide:width=4"};
  const auto points = query_points(scene, 150, 50, 8);
  auto brute = make_accelerator("brute_force");
  brute->build(scene);
  std::vector<ClosestPoint> expected(points.size()), got(points.size());
  brute->closest_points(points, expected);
  for (const auto& spec : specs) {
    auto accel = make_accelerator(spec);
    accel->build(scene);
    accel->closest_points(points, got);
    for (std::size_t i = 0; i < points.size(); ++i) ASSERT_EQ(got[i].distance, expected[i].distance) << spec << " " << i;
  }
}

}  // namespace
}  // namespace rayaccel
