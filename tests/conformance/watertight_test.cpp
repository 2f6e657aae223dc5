// Conformance: watertightness. Rays fired from inside a closed mesh with shared vertices (a tessellated sphere, a
// subdivided cube) toward its vertices and edge midpoints, along the axes and in random directions, never escape:
// the watertight kernel guarantees it for brute force, and a structure must not lose the hit by culling a node or
// cell the ray only touches at an edge or corner.
#include <gtest/gtest.h>

#include <vector>

#include "oracle.h"
#include "test_scenes.h"

namespace rayaccel::conformance {
namespace {

class Watertight : public ConformanceTest {};

/// Every ray must hit (brute force first: a miss there is a kernel leak), then the structure must agree.
void expect_no_escape(const Accelerator& accel, const Scene& scene, const std::vector<Ray>& rays,
                      const std::string& label) {
  const std::vector<Hit> reference = brute_force_hits(scene, rays);
  int kernel_leaks = 0, structure_leaks = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (!reference[i].found() && ++kernel_leaks <= 5) ADD_FAILURE() << label << ": brute force leaks " << describe(rays[i]);
    if (!accel.intersect(rays[i]).found() && ++structure_leaks <= 5) {
      ADD_FAILURE() << accel.spec() << " / " << label << ": ray escapes " << describe(rays[i]);
    }
  }
  EXPECT_EQ(kernel_leaks, 0) << label << ": rays escaping brute force";
  EXPECT_EQ(structure_leaks, 0) << label << ": rays escaping " << accel.spec();
  expect_matches_reference(accel, scene, rays, reference, label);
}

/// Random rays from random points strictly inside the ball of radius `inner`.
std::vector<Ray> random_inside_rays(float inner, std::size_t count, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Ray> rays(count);
  for (Ray& ray : rays) {
    ray.origin = rng.unit_vector() * (inner * rng.uniform());
    ray.direction = rng.unit_vector();
  }
  return rays;
}

/// The 26 directions to the neighbours of a lattice point, with +0 and -0 for zero components.
std::vector<Ray> lattice_neighbour_rays(const Vec3& origin) {
  std::vector<Ray> rays;
  for (int x = -1; x <= 1; ++x) {
    for (int y = -1; y <= 1; ++y) {
      for (int z = -1; z <= 1; ++z) {
        if (x == 0 && y == 0 && z == 0) continue;
        for (float zero : {0.0f, -0.0f}) {
          Ray ray;
          ray.origin = origin;
          ray.direction = {x ? static_cast<float>(x) : zero, y ? static_cast<float>(y) : zero,
                           z ? static_cast<float>(z) : zero};
          rays.push_back(ray);
        }
      }
    }
  }
  return rays;
}

TEST_P(Watertight, ClosedSphereMesh) {
  const TriangleMesh mesh = closed_sphere_mesh(16, 32);
  const Scene scene = Scene::from_mesh(mesh, "closed sphere");
  auto accel = build_checked(GetParam(), scene);
  const std::vector<Vec3> origins{{0.0f, 0.0f, 0.0f}, {0.1f, 0.2f, -0.3f}, {0.0f, 0.9f, 0.0f}, {-0.5f, 0.0f, 0.5f}};
  expect_no_escape(*accel, scene, rays_to_vertices_and_edges(mesh, origins), "sphere, rays at vertices and edges");
  expect_no_escape(*accel, scene, random_inside_rays(0.9f, 1500, 51), "sphere, random rays from inside");
  expect_no_escape(*accel, scene, lattice_neighbour_rays({0.0f, 0.0f, 0.0f}), "sphere, axis and diagonal rays");
}

TEST_P(Watertight, ClosedBoxMesh) {
  const TriangleMesh mesh = closed_box_mesh(8);
  const Scene scene = Scene::from_mesh(mesh, "closed box");
  auto accel = build_checked(GetParam(), scene);
  const std::vector<Vec3> origins{{0.0f, 0.0f, 0.0f}, {0.5f, -0.25f, 0.125f}, {0.9f, 0.9f, 0.9f}};
  expect_no_escape(*accel, scene, rays_to_vertices_and_edges(mesh, origins), "box, rays at vertices and edges");
  expect_no_escape(*accel, scene, random_inside_rays(0.95f, 1500, 52), "box, random rays from inside");
  // From lattice points, the 26 lattice directions run exactly through the quads' edges and corners.
  std::vector<Ray> rays;
  for (const Vec3& o : {Vec3{0.0f, 0.0f, 0.0f}, Vec3{0.25f, -0.5f, 0.75f}, Vec3{-0.75f, -0.75f, -0.75f}}) {
    const std::vector<Ray> more = lattice_neighbour_rays(o);
    rays.insert(rays.end(), more.begin(), more.end());
  }
  expect_no_escape(*accel, scene, rays, "box, lattice-direction rays");
}

INSTANTIATE_TEST_SUITE_P(Conformance, Watertight, ::testing::ValuesIn(variant_specs()), spec_test_name);

}  // namespace
}  // namespace rayaccel::conformance
