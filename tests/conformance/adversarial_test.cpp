// Conformance: inputs that break careless structures. Empty and one-primitive scenes, duplicates, zero-area
// triangles, huge and tiny coordinates, axis-parallel rays with +0 / -0 components grazing axis-aligned quads, rays
// starting on surfaces, and degenerate rays (t_max = 0, t_min = t_max, NaN, Inf, zero direction). Nothing may crash
// and every answer must match brute force; bad rays never hit.
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "oracle.h"
#include "test_scenes.h"
#include "../float_specials.h"

namespace rayaccel::conformance {
namespace {

class Adversarial : public ConformanceTest {};

using test_values::kNaN;

/// Degenerate rays about the scene, checked against brute force; bad (void) rays must miss on both sides.
void expect_degenerate_rays_match(const Accelerator& accel, const Scene& scene, const std::string& label) {
  const std::vector<Ray> rays = degenerate_rays(scene.bounds());
  const std::vector<Hit> reference = brute_force_hits(scene, rays);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (!is_bad_ray(rays[i])) continue;
    EXPECT_FALSE(reference[i].found()) << label << ": brute force hit with a void ray " << describe(rays[i]);
    EXPECT_FALSE(accel.intersect(rays[i]).found()) << label << ": a void ray hit: " << describe(rays[i]);
    EXPECT_FALSE(accel.occluded(rays[i])) << label << ": a void ray is occluded: " << describe(rays[i]);
  }
  expect_matches_reference(accel, scene, rays, reference, label + " degenerate rays");
}

/// Random, camera and degenerate rays about the scene, checked against brute force.
void expect_all_ray_kinds_match(const Accelerator& accel, const Scene& scene, const std::string& label) {
  expect_matches_brute_force(accel, scene, random_rays(scene.bounds(), 1000, 41), label + " random rays");
  expect_matches_brute_force(accel, scene, camera_rays(scene.bounds(), 24, 16), label + " camera rays");
  expect_degenerate_rays_match(accel, scene, label);
}

TEST_P(Adversarial, EmptyScenesMissEverything) {
  const Scene empty_mesh = Scene::from_mesh({}, "empty mesh");
  const Scene empty_spheres = Scene::from_spheres({}, "empty spheres");
  const Scene empty_user = Scene::from_user({}, "empty user");
  TriangleMesh all_invalid = random_soup_mesh(50, 0.2f, 3);
  for (std::size_t i = 0; i < all_invalid.triangles.size(); ++i) all_invalid.vertices[all_invalid.triangles[i][0]].x = kNaN;
  const Scene invalid = Scene::from_mesh(std::move(all_invalid), "all invalid");
  ASSERT_EQ(invalid.invalid_count(), 50u);
  const std::vector<Ray> rays = random_rays(AABB(Vec3{0.0f}, Vec3{1.0f}), 300, 42);
  for (const Scene* scene : {&empty_mesh, &empty_spheres, &empty_user, &invalid}) {
    auto accel = build_checked(GetParam(), *scene);
    for (const Ray& ray : rays) {
      ASSERT_FALSE(accel->intersect(ray).found()) << scene->name() << ": " << describe(ray);
      ASSERT_FALSE(accel->occluded(ray)) << scene->name() << ": " << describe(ray);
    }
    expect_all_ray_kinds_match(*accel, *scene, scene->name());
  }
}

TEST_P(Adversarial, OneTriangle) {
  TriangleMesh mesh;
  mesh.vertices = {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  mesh.triangles = {{0, 1, 2}};
  const Scene scene = Scene::from_mesh(mesh, "one triangle");
  auto accel = build_checked(GetParam(), scene);
  expect_all_ray_kinds_match(*accel, scene, scene.name());
  expect_matches_brute_force(*accel, scene, rays_to_vertices_and_edges(mesh, {{0.2f, 0.3f, 1.0f}, {-1, -1, -1}}),
                             "one triangle, rays at vertices and edges");
  expect_matches_brute_force(*accel, scene, axis_parallel_rays({-0.5f, 0.0f, 0.25f, 1.0f}), "one triangle, axis rays");
}

TEST_P(Adversarial, DuplicateTriangles) {
  TriangleMesh mesh = random_soup_mesh(100, 0.3f, 4);
  const std::size_t base = mesh.triangles.size();
  for (int copy = 0; copy < 400; ++copy) {
    const auto& tri = mesh.triangles[static_cast<std::size_t>(copy) % 3];
    // Same vertices, same indices; every third copy with rotated vertex order.
    if (copy % 3 == 2) {
      mesh.triangles.push_back({tri[1], tri[2], tri[0]});
    } else {
      mesh.triangles.push_back(tri);
    }
  }
  // Coincident vertices stored twice (distinct indices, equal positions).
  for (std::size_t i = 0; i < 200; ++i) {
    const auto tri = mesh.triangles[i % base];
    const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
    for (std::uint32_t k : tri) mesh.vertices.push_back(mesh.vertices[k]);
    mesh.triangles.push_back({first, first + 1, first + 2});
  }
  const Scene scene = Scene::from_mesh(std::move(mesh), "duplicates");
  auto accel = build_checked(GetParam(), scene);
  expect_all_ray_kinds_match(*accel, scene, scene.name());
  expect_matches_brute_force(*accel, scene, rays_from_surfaces(scene, 500, 43), "duplicates, rays from surfaces");
}

TEST_P(Adversarial, ZeroAreaTriangles) {
  TriangleMesh mesh = random_soup_mesh(300, 0.2f, 5);
  Rng rng(6);
  for (int i = 0; i < 600; ++i) {
    const Vec3 a = rng.in_box(AABB(Vec3{0.0f}, Vec3{1.0f}));
    const Vec3 d = rng.unit_vector() * 0.2f;
    const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
    switch (i % 4) {
      case 0: mesh.vertices.insert(mesh.vertices.end(), {a, a + d, a + d * 0.5f}); break;   // collinear (inexact)
      case 1: mesh.vertices.insert(mesh.vertices.end(), {a, a, a}); break;                  // a point
      case 2: mesh.vertices.insert(mesh.vertices.end(), {a, a + d, a + d}); break;          // two equal vertices
      default:                                                                              // exactly collinear, axis-aligned
        mesh.vertices.insert(mesh.vertices.end(), {a, {a.x + 0.25f, a.y, a.z}, {a.x + 0.5f, a.y, a.z}});
    }
    mesh.triangles.push_back({first, first + 1, first + 2});
  }
  const Scene scene = Scene::from_mesh(std::move(mesh), "zero area");
  EXPECT_GE(scene.degenerate_count(), 450u);
  auto accel = build_checked(GetParam(), scene);
  expect_all_ray_kinds_match(*accel, scene, scene.name());
  expect_matches_brute_force(*accel, scene, rays_from_surfaces(scene, 800, 44), "zero area, rays from surfaces");
}

TEST_P(Adversarial, HugeCoordinates) {
  const TriangleMesh soup = random_soup_mesh(1000, 0.12f, 7);
  const Scene giga = Scene::from_mesh(transformed(soup, 1e10f, Vec3{1e10f, -2e10f, 3e10f}), "soup at 1e10");
  const Scene scaled = Scene::from_mesh(transformed(soup, 1e15f, Vec3{1e15f, -2e15f, 3e15f}), "soup at 1e15");
  // Offset far beyond the triangles' size: many vertices round together, some triangles collapse.
  const Scene offset = Scene::from_mesh(transformed(soup, 1e8f, Vec3{1e15f, 1e15f, -1e15f}), "soup offset 1e15");
  for (const Scene* scene : {&giga, &scaled, &offset}) {
    auto accel = build_checked(GetParam(), *scene);
    expect_all_ray_kinds_match(*accel, *scene, scene->name());
  }
  // A power-of-two scale keeps the lattice exact, so axis rays still run exactly in and between its planes.
  constexpr float kScale = 0x1p50f;
  const Scene lattice = Scene::from_mesh(transformed(quad_lattice_mesh(5), kScale, Vec3{}), "lattice at 2^50");
  auto accel = build_checked(GetParam(), lattice);
  std::vector<Ray> rays = axis_parallel_rays({-kScale, 0.0f, 0.5f * kScale, 2.0f * kScale, 4.0f * kScale});
  expect_matches_brute_force(*accel, lattice, rays, lattice.name() + " axis rays");
  expect_all_ray_kinds_match(*accel, lattice, lattice.name());
}

TEST_P(Adversarial, TinyCoordinates) {
  const TriangleMesh mesh = random_soup_mesh(1000, 0.12f, 8);
  const Scene nano = Scene::from_mesh(transformed(mesh, 1e-9f, Vec3{}), "soup at 1e-9");
  const Scene atto = Scene::from_mesh(transformed(mesh, 1e-18f, Vec3{1e-18f}), "soup at 1e-18");
  for (const Scene* scene : {&nano, &atto}) {
    auto accel = build_checked(GetParam(), *scene);
    expect_all_ray_kinds_match(*accel, *scene, scene->name());
  }
  constexpr float kScale = 0x1p-60f;
  const Scene lattice = Scene::from_mesh(transformed(quad_lattice_mesh(5), kScale, Vec3{}), "lattice at 2^-60");
  auto lattice_accel = build_checked(GetParam(), lattice);
  expect_matches_brute_force(*lattice_accel, lattice,
                             axis_parallel_rays({-kScale, 0.0f, 0.5f * kScale, 2.0f * kScale, 4.0f * kScale}),
                             lattice.name() + " axis rays");
}

TEST_P(Adversarial, AxisParallelRaysGrazeAxisAlignedQuads) {
  const Scene lattice = Scene::from_mesh(quad_lattice_mesh(6), "quad lattice");
  auto accel = build_checked(GetParam(), lattice);
  expect_matches_brute_force(*accel, lattice, axis_parallel_rays({-1.0f, 0.0f, 0.5f, 2.0f, 5.0f}),
                             "quad lattice axis rays");
  const Scene box = Scene::from_mesh(closed_box_mesh(4), "box mesh");
  auto box_accel = build_checked(GetParam(), box);
  expect_matches_brute_force(*box_accel, box, axis_parallel_rays({-1.5f, -1.0f, -0.25f, 0.0f, 1.0f}),
                             "box mesh axis rays");
}

TEST_P(Adversarial, RaysStartingOnSurfaces) {
  for (const SceneCase& c : small_scene_cases()) {
    auto accel = build_checked(GetParam(), c.scene);
    expect_matches_brute_force(*accel, c.scene, rays_from_surfaces(c.scene, 600, 45), c.name + " rays from surfaces");
  }
}

TEST_P(Adversarial, RaysASubnormalDistanceFromPlanesAtZero) {
  // Quads on the planes x = 0..5 and y = 0..5 and a closed box [-1, 1]^3 moved so that faces lie on z = 0 and y = 0:
  // flat primitive boxes at 0. Rays start on those planes and then a subnormal distance off them (as pbrt-style
  // offsets from exact points give) or FLT_MIN off, pointing away from, toward and along the plane. Exactly, a ray
  // leaving the plane never meets it and a ray toward it meets it at a tiny t; structures that compute with a
  // rounded or moved origin (the wide BVH moves subnormal coordinates to 0 for its box tests) must agree with brute
  // force on every one. Near an edge line the kernel's float sheared coordinates underflow, so it must decide such
  // edges from the vertices in double.
  TriangleMesh merged = quad_lattice_mesh(6);
  const TriangleMesh box = transformed(closed_box_mesh(2), 1.0f, Vec3{2.5f, 1.0f, 1.0f});
  const auto offset = static_cast<std::uint32_t>(merged.vertices.size());
  merged.vertices.insert(merged.vertices.end(), box.vertices.begin(), box.vertices.end());
  for (auto t : box.triangles) merged.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  const Scene scene = Scene::from_mesh(std::move(merged), "planes at zero");
  auto accel = build_checked(GetParam(), scene);
  constexpr float kOffsets[] = {0x1p-149f, -0x1p-149f, 0x1p-140f, -0x1p-130f, 0x1p-126f, -0x1p-126f, 0.0f, -0.0f};
  Rng rng(46);
  std::vector<Ray> rays;
  for (int i = 0; i < 3000; ++i) {
    // A point on x = 0, y = 0 or z = 0 within the scene, then that coordinate (and sometimes a second one, which
    // puts the origin on or next to an edge line of the quads) offset.
    Vec3 origin{rng.uniform(0.0f, 5.0f), rng.uniform(0.0f, 5.0f), rng.uniform(0.0f, 2.0f)};
    const std::uint32_t axis = rng.below(3);
    origin[axis] = kOffsets[rng.below(8)];
    if (rng.below(4) == 0) origin[(axis + 1) % 3] = kOffsets[rng.below(8)];
    Vec3 d = rng.unit_vector();
    switch (rng.below(4)) {
      case 0: d[axis] = 0.0f; break;                           // along the plane
      case 1: d[axis] = 0x1p-20f * (d[axis] < 0 ? -1 : 1); break;  // almost along it
      default: break;
    }
    const float t_min = rng.below(5) == 0 ? 0x1p-149f : 0.0f;
    rays.push_back(Ray{origin, t_min, d, rng.below(3) == 0 ? 0.5f : std::numeric_limits<float>::infinity()});
  }
  expect_matches_brute_force(*accel, scene, rays, "rays a subnormal distance from planes at 0");
}

TEST_P(Adversarial, DegenerateRays) {
  for (const SceneCase& c : small_scene_cases()) {
    auto accel = build_checked(GetParam(), c.scene);
    expect_degenerate_rays_match(*accel, c.scene, c.name);
  }
  const Scene spheres = random_sphere_scene(300, 46);
  auto accel = build_checked(GetParam(), spheres);
  expect_degenerate_rays_match(*accel, spheres, spheres.name());
}

INSTANTIATE_TEST_SUITE_P(Conformance, Adversarial, ::testing::ValuesIn(variant_specs()), spec_test_name);

}  // namespace
}  // namespace rayaccel::conformance
