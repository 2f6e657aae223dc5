// All-hits queries: every structure that supports them returns exactly brute force's crossings, and rays through the
// vertices, edges and faces of closed meshes cross them an odd number of times from inside and an even number from
// outside (the voxel solid's occupancy and the meshes' closedness are the independent references).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "../conformance/test_scenes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/query/closed_mesh.h"
#include "rayaccel/scene/builtin_scenes.h"
#include "query_structures.h"
#include "voxel_shape.h"

namespace rayaccel {
namespace {

using conformance::Rng;
using testing::query_structures;

/// Rays through the voxel solid's grid points (vertices, edge midpoints, face centres and voxel centres: multiples of
/// 1/2), along the axes, face diagonals, space diagonals and skew integer directions, from points on the same grid.
std::vector<Ray> voxel_grid_rays() {
  std::vector<Ray> rays;
  const Vec3 directions[] = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1},  {1, 1, 0},  {0, 1, -1}, {-1, 0, 1},
                             {1, 1, 1}, {-1, 1, 1}, {1, 2, 3},  {-2, 1, 1}, {3, -1, 2}, {1, -2, -1}};
  for (int x = -1; x <= 10; ++x) {
    for (int y = -1; y <= 10; ++y) {
      for (int z = -1; z <= 10; ++z) {
        const Vec3 origin{0.5f * float(x), 0.5f * float(y), 0.5f * float(z)};
        for (const Vec3& d : directions) rays.push_back(Ray{origin, 0.0f, d, std::numeric_limits<float>::infinity()});
      }
    }
  }
  return rays;
}

/// Hits of every triangle the watertight test reports (no crossing rule): several per crossing through an edge.
std::size_t naive_hit_count(const Scene& scene, const Ray& ray) {
  const PreparedRay prepared(ray);
  std::size_t count = 0;
  for (std::uint32_t id = 0; id < scene.primitive_count(); ++id) {
    Hit hit = Hit::begin(prepared);
    count += scene.intersect(id, prepared, hit) ? 1 : 0;
  }
  return count;
}

void expect_same_hits(const std::vector<Hit>& expected, const std::vector<Hit>& got, const std::string& what) {
  ASSERT_EQ(expected.size(), got.size()) << what;
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(expected[i].prim_id, got[i].prim_id) << what << " hit " << i;
    EXPECT_EQ(expected[i].t, got[i].t) << what << " hit " << i;
    EXPECT_EQ(expected[i].u, got[i].u) << what << " hit " << i;
    EXPECT_EQ(expected[i].v, got[i].v) << what << " hit " << i;
  }
}

TEST(AllHits, VoxelSolidParityThroughVerticesEdgesAndFaces) {
  const Scene scene = Scene::from_mesh(testing::voxel_shape_mesh(), "voxels");
  ASSERT_TRUE(check_closed(scene).closed());
  const auto structures = query_structures(scene);
  ASSERT_GE(structures.size(), 3u);
  std::size_t checked = 0, merged = 0, inside_origins = 0;
  std::vector<Hit> expected, got;
  for (const Ray& ray : voxel_grid_rays()) {
    const double fraction = testing::voxel_inside_fraction(ray.origin);
    const std::size_t count = structures[0]->all_hits(ray, expected);
    ASSERT_EQ(count, expected.size());
    ASSERT_EQ(structures[0]->spec(), "brute_force");
    if (fraction == 0.0 || fraction == 1.0) {  // origin off the surface: the parity is known
      ++checked;
      inside_origins += fraction == 1.0 ? 1 : 0;
      EXPECT_EQ(count % 2, fraction == 1.0 ? 1u : 0u)
          << "origin (" << ray.origin.x << ", " << ray.origin.y << ", " << ray.origin.z << ") direction ("
          << ray.direction.x << ", " << ray.direction.y << ", " << ray.direction.z << ")";
    }
    merged += naive_hit_count(scene, ray) != count ? 1 : 0;
    for (std::size_t s = 1; s < structures.size(); ++s) {
      structures[s]->all_hits(ray, got);
      expect_same_hits(expected, got, structures[s]->spec());
      if (::testing::Test::HasFailure()) return;
    }
  }
  EXPECT_GT(inside_origins, 100u);
  EXPECT_GT(checked, 10000u);
  // The rays through edges and vertices, where counting triangle hits would count one crossing several times.
  EXPECT_GT(merged, 1000u);
}

TEST(AllHits, ParityHoldsAMillionUnitsFromTheOrigin) {
  // The voxel solid moved by 2^20 on every axis (still exact: its grid points need 22 bits), where a float's ulp is
  // 1/8: the same rays through its vertices, edges and faces, moved with it, cross it as near the origin.
  const float offset = 0x1p20f;
  TriangleMesh mesh = testing::voxel_shape_mesh();
  for (Vec3& v : mesh.vertices) v = v + Vec3{offset};
  const Scene scene = Scene::from_mesh(mesh, "far voxels");
  std::vector<std::unique_ptr<Accelerator>> structures;
  for (const char* spec : {"brute_force", "bvh", "bvh_wide"}) {
    structures.push_back(make_accelerator(spec));
    structures.back()->build(scene);
  }
  std::vector<Hit> expected, got;
  std::size_t checked = 0;
  for (Ray ray : voxel_grid_rays()) {
    const double fraction = testing::voxel_inside_fraction(ray.origin);
    ray.origin = ray.origin + Vec3{offset};
    const std::size_t count = structures[0]->all_hits(ray, expected);
    if (fraction == 0.0 || fraction == 1.0) {
      ++checked;
      ASSERT_EQ(count % 2, fraction == 1.0 ? 1u : 0u)
          << "origin (" << ray.origin.x << ", " << ray.origin.y << ", " << ray.origin.z << ")";
    }
    for (std::size_t s = 1; s < structures.size(); ++s) {
      structures[s]->all_hits(ray, got);
      expect_same_hits(expected, got, structures[s]->spec());
    }
    if (::testing::Test::HasFailure()) return;
  }
  EXPECT_GT(checked, 10000u);
}

TEST(AllHits, ClosedMeshesCrossedEvenlyThroughTheirVertices) {
  // Rays from outside through every vertex and edge midpoint: an even number of crossings each.
  const std::vector<std::pair<std::string, TriangleMesh>> meshes = {
      {"uv sphere", conformance::closed_sphere_mesh(9, 14)},
      {"box", conformance::closed_box_mesh(4)},
      {"icosphere", make_builtin_scene("sphere", {{"level", "2"}}).mesh()}};
  for (const auto& [name, mesh] : meshes) {
    const Scene scene = Scene::from_mesh(mesh, name);
    ASSERT_TRUE(check_closed(scene).closed()) << name;
    const auto structures = query_structures(scene);
    auto rays = conformance::rays_to_vertices_and_edges(mesh, {{5.0f, 0.25f, 0.5f}, {-0.125f, -7.0f, 0.375f}});
    // Axis-parallel rays exactly through every vertex (one coordinate moved outside the mesh, the others kept).
    for (const Vec3& v : mesh.vertices) {
      for (int a = 0; a < 3; ++a) {
        Vec3 origin = v, direction{0, 0, 0};
        origin[a] = 5.0f;
        direction[a] = -1.0f;
        rays.push_back(Ray{origin, 0.0f, direction, std::numeric_limits<float>::infinity()});
      }
    }
    std::vector<Hit> expected, got;
    std::size_t merged = 0;
    for (const Ray& ray : rays) {
      const std::size_t count = structures[0]->all_hits(ray, expected);
      EXPECT_EQ(count % 2, 0u) << name;
      merged += naive_hit_count(scene, ray) != count ? 1 : 0;
      for (std::size_t s = 1; s < structures.size(); ++s) {
        structures[s]->all_hits(ray, got);
        expect_same_hits(expected, got, name + " " + structures[s]->spec());
      }
      if (::testing::Test::HasFailure()) return;
    }
    EXPECT_GT(merged, rays.size() / 4) << name;
  }
}

TEST(AllHits, RandomRaysMatchBruteForceOnSoupsWithTiesCapsAndCounts) {
  // A random soup (open, overlapping) and the conformance rays: the crossings of each structure, the cap, the count.
  const Scene scene = Scene::from_mesh(conformance::random_soup_mesh(800, 0.3f, 7), "soup");
  const auto structures = query_structures(scene);
  const auto rays = conformance::random_rays(scene.bounds(), 600, 11);
  std::vector<Hit> expected, got;
  std::size_t multi = 0;
  for (const Ray& ray : rays) {
    const std::size_t count = structures[0]->all_hits(ray, expected);
    multi += count >= 3 ? 1 : 0;
    for (std::size_t i = 1; i < expected.size(); ++i) ASSERT_LE(expected[i - 1].t, expected[i].t);
    // Each crossing is the closest hit of its own triangle.
    for (const Hit& h : expected) {
      const PreparedRay prepared(ray);
      Hit alone = Hit::begin(prepared);
      ASSERT_TRUE(scene.intersect(h.prim_id, prepared, alone));
      EXPECT_EQ(alone.t, h.t);
    }
    // The first crossing is the closest hit.
    const Hit closest = structures[0]->intersect(ray);
    if (!expected.empty()) {
      EXPECT_EQ(closest.t, expected[0].t);
    }
    for (const auto& accel : structures) {
      EXPECT_EQ(accel->count_hits(ray), count) << accel->spec();
      const std::size_t capped = accel->all_hits(ray, got, 2);
      EXPECT_EQ(capped, count) << accel->spec();
      ASSERT_EQ(got.size(), std::min<std::size_t>(2, count)) << accel->spec();
      for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i].t, expected[i].t) << accel->spec();
      accel->all_hits(ray, got);
      expect_same_hits(expected, got, accel->spec());
    }
    if (::testing::Test::HasFailure()) return;
  }
  EXPECT_GT(multi, 50u);
}

TEST(AllHits, BatchCountsMatchSingleQueries) {
  const Scene scene = Scene::from_mesh(testing::voxel_shape_mesh(), "voxels");
  auto accel = make_accelerator("bvh_wide");
  accel->build(scene);
  const auto rays = voxel_grid_rays();
  std::vector<std::uint32_t> counts(rays.size());
  accel->count_hits(rays, counts);
  for (std::size_t i = 0; i < rays.size(); i += 7) ASSERT_EQ(counts[i], accel->count_hits(rays[i]));
  EXPECT_THROW(accel->count_hits(rays, std::span<std::uint32_t>(counts).first(3)), Error);
}

TEST(AllHits, UnsupportedStructuresAndScenesSayWhy) {
  const Scene scene = Scene::from_mesh(testing::voxel_shape_mesh(), "voxels");
  auto kd = make_accelerator("kdtree");
  kd->build(scene);
  EXPECT_FALSE(kd->supports_queries());
  std::vector<Hit> hits;
  try {
    kd->all_hits(Ray{}, hits);
    ADD_FAILURE() << "kdtree answered an all-hits query";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("kdtree"), std::string::npos) << e.what();
  }
  EXPECT_THROW(kd->closest_point({0, 0, 0}), Error);
  const Scene spheres = conformance::random_sphere_scene(20, 3);
  for (const char* spec : {"brute_force", "bvh", "bvh_wide"}) {
    auto accel = make_accelerator(spec);
    accel->build(spheres);
    try {
      accel->all_hits(Ray{{0, 0, -5}, 0.0f, {0, 0, 1}, 10.0f}, hits);
      ADD_FAILURE() << spec << " answered an all-hits query on spheres";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("spheres"), std::string::npos) << e.what();
    }
  }
}

TEST(AllHits, VoidRaysHaveNoCrossings) {
  const Scene scene = Scene::from_mesh(testing::voxel_shape_mesh(), "voxels");
  for (const char* spec : {"brute_force", "bvh", "bvh_wide"}) {
    auto accel = make_accelerator(spec);
    accel->build(scene);
    for (const Ray& ray : conformance::degenerate_rays(scene.bounds())) {
      if (!conformance::is_bad_ray(ray)) continue;
      std::vector<Hit> hits(3);
      EXPECT_EQ(accel->all_hits(ray, hits), 0u) << spec;
      EXPECT_TRUE(hits.empty()) << spec;
    }
  }
}

}  // namespace
}  // namespace rayaccel
