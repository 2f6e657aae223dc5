// Inside tests and signed distance against closed forms: the voxel solid's occupancy (and, on its surface, the
// fraction of a small ball inside it, which the generalised winding number equals), and a UV sphere's radius.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "../conformance/test_scenes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/query/closed_mesh.h"
#include "rayaccel/query/inside.h"
#include "rayaccel/query/signed_distance.h"
#include "voxel_shape.h"

namespace rayaccel {
namespace {

using conformance::Rng;

/// The half-integer grid over and around the voxel solid: voxel centres, face centres, edge midpoints, vertices.
std::vector<Vec3> voxel_grid_points() {
  std::vector<Vec3> points;
  for (int x = -1; x <= 9; ++x) {
    for (int y = -1; y <= 9; ++y) {
      for (int z = -1; z <= 9; ++z) points.push_back({0.5f * float(x), 0.5f * float(y), 0.5f * float(z)});
    }
  }
  return points;
}

TEST(Inside, ParityMatchesTheVoxelOccupancyOffTheSurface) {
  const Scene scene = Scene::from_mesh(testing::voxel_shape_mesh(), "voxels");
  // Grid points off the surface, and points a hundredth from each face centre, on both sides.
  std::vector<Vec3> points;
  for (const Vec3& p : voxel_grid_points()) {
    const double f = testing::voxel_inside_fraction(p);
    if (f == 0.0 || f == 1.0) points.push_back(p);
  }
  for (const Vec3& p : voxel_grid_points()) {
    // Face centres: one integer coordinate (the face's plane), half the small ball inside.
    int integer_axes = 0;
    for (int a = 0; a < 3; ++a) integer_axes += p[a] == std::floor(p[a]) ? 1 : 0;
    if (integer_axes != 1 || testing::voxel_inside_fraction(p) != 0.5) continue;
    for (int a = 0; a < 3; ++a) {
      if (p[a] != std::floor(p[a])) continue;
      for (float offset : {-0.01f, 0.01f}) {
        Vec3 q = p;
        q[a] += offset;
        points.push_back(q);
      }
    }
  }
  for (const char* spec : {"brute_force", "bvh", "bvh:builder=sbvh", "bvh_wide", "bvh_wide:width=4"}) {
    auto accel = make_accelerator(spec);
    accel->build(scene);
    for (int rays : {1, 3, 7}) {
      std::vector<std::uint8_t> inside(points.size());
      inside_by_parity(*accel, points, inside, {.ray_count = rays});
      std::size_t inside_count = 0;
      for (std::size_t i = 0; i < points.size(); ++i) {
        const bool expected = testing::voxel_inside_fraction(points[i]) == 1.0;
        inside_count += expected ? 1 : 0;
        ASSERT_EQ(inside[i] != 0, expected) << spec << " rays " << rays << " point (" << points[i].x << ", "
                                            << points[i].y << ", " << points[i].z << ")";
      }
      EXPECT_GT(inside_count, 100u);
    }
  }
}

TEST(Inside, WindingNumberIsTheInsideFractionEverywhereOnTheGrid) {
  // 1 inside, 0 outside, 1/2 on faces, k/4 on edges and k/8 at vertices.
  const Scene scene = Scene::from_mesh(testing::voxel_shape_mesh(), "voxels");
  const auto points = voxel_grid_points();
  std::vector<double> winding(points.size());
  winding_numbers(scene, points, winding);
  std::size_t fractional = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double expected = testing::voxel_inside_fraction(points[i]);
    fractional += expected != 0.0 && expected != 1.0 ? 1 : 0;
    // A sum of some 300 solid angles, each within a few double ulps.
    ASSERT_NEAR(winding[i], expected, 1e-12) << "point (" << points[i].x << ", " << points[i].y << ", "
                                             << points[i].z << ")";
  }
  EXPECT_GT(fractional, 100u);
}

TEST(Inside, OpenMeshWindingNumberDegradesSmoothlyWhereParityCannotDecide) {
  // The voxel solid with its floor (every face at z = 0) removed: not closed; deep inside, the winding number stays
  // near 1, well above 1/2, and far outside near 0.
  TriangleMesh mesh = testing::voxel_shape_mesh();
  std::vector<std::array<std::uint32_t, 3>> kept;
  for (const auto& t : mesh.triangles) {
    if (!(mesh.vertices[t[0]].z == 0 && mesh.vertices[t[1]].z == 0 && mesh.vertices[t[2]].z == 0)) kept.push_back(t);
  }
  ASSERT_LT(kept.size(), mesh.triangles.size());
  mesh.triangles = kept;
  const Scene scene = Scene::from_mesh(mesh, "open voxels");
  EXPECT_FALSE(check_closed(scene).closed());
  const std::vector<Vec3> points = {{0.5f, 0.5f, 2.5f}, {0.5f, 2.5f, 0.5f}, {20, 20, 20}, {0.5f, 0.5f, -30}};
  std::vector<double> winding(points.size());
  winding_numbers(scene, points, winding);
  EXPECT_GT(winding[0], 0.75);
  EXPECT_GT(winding[1], 0.5);
  EXPECT_LT(std::fabs(winding[2]), 0.01);
  EXPECT_LT(std::fabs(winding[3]), 0.01);
}

TEST(Inside, SphereRadiusDecidesAndSignedDistanceAgrees) {
  // A UV sphere inscribed in the unit sphere: |p| >= 1 is outside the polyhedron, and |p| < 0.9 inside (no face
  // plane comes nearer the centre than the cosine of a cell's diagonal, 18.75 degrees here: 0.947).
  const int stacks = 16, slices = 24;
  const Scene scene = Scene::from_mesh(conformance::closed_sphere_mesh(stacks, slices), "sphere");
  ASSERT_TRUE(check_closed(scene).closed());
  auto accel = make_accelerator("bvh_wide");
  accel->build(scene);
  auto brute = make_accelerator("brute_force");
  brute->build(scene);
  Rng rng(21);
  const float inner = 0.9f;
  std::vector<Vec3> points;
  std::vector<int> expected;  // 1 inside, 0 outside
  while (points.size() < 3000) {
    const Vec3 p = rng.in_box(AABB{{-1.5f, -1.5f, -1.5f}, {1.5f, 1.5f, 1.5f}});
    const float r = length(p);
    if (r < inner || r >= 1.0f) {
      points.push_back(p);
      expected.push_back(r < inner ? 1 : 0);
    }
  }
  std::vector<std::uint8_t> inside(points.size());
  inside_by_parity(*accel, points, inside);
  std::vector<float> distance(points.size());
  std::vector<ClosestPoint> closest(points.size()), reference(points.size());
  signed_distances(*accel, points, distance, closest);
  brute->closest_points(points, reference);
  for (std::size_t i = 0; i < points.size(); ++i) {
    ASSERT_EQ(inside[i], expected[i]) << i;
    EXPECT_EQ(std::fabs(distance[i]), reference[i].distance) << i;
    EXPECT_EQ(distance[i] < 0.0f, expected[i] == 1) << i;
    // Outside the unit sphere, which holds the polyhedron, the distance is at least |p| - 1.
    if (expected[i] == 0) {
      EXPECT_GE(distance[i], length(points[i]) - 1.0f - 1e-6f) << i;
    }
  }
}

TEST(Inside, BadInputIsRefused) {
  const Scene scene = Scene::from_mesh(testing::voxel_shape_mesh(), "voxels");
  auto accel = make_accelerator("bvh");
  accel->build(scene);
  std::vector<Vec3> points = {{0, 0, 0}};
  std::vector<std::uint8_t> inside(1);
  EXPECT_THROW(inside_by_parity(*accel, points, inside, {.ray_count = 2}), Error);
  EXPECT_THROW(inside_by_parity(*accel, points, inside, {.ray_count = 9}), Error);
  std::vector<std::uint8_t> wrong(2);
  EXPECT_THROW(inside_by_parity(*accel, points, wrong), Error);
  auto grid = make_accelerator("grid");
  grid->build(scene);
  EXPECT_THROW(inside_by_parity(*grid, points, inside), Error);
  std::vector<double> winding(1);
  const Scene spheres = conformance::random_sphere_scene(3, 1);
  EXPECT_THROW(winding_numbers(spheres, points, winding), Error);
}

}  // namespace
}  // namespace rayaccel
