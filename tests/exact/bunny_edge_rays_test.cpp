// Issue #19, item 1: 1,024 rays aimed exactly at vertices and edge points of the bunny; brute force and the default
// structure (bvh_wide) must agree with exact rational arithmetic on every one. Also measures how often the kernel's
// float edge functions fall inside their error bound (the exact band) on these rays and on ordinary camera rays.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "../conformance/test_scenes.h"
#include "../shared_scenes.h"
#include "exact_reference.h"
#include "far_rays.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/geometry/ray_triangle.h"
#include "rayaccel/render/camera.h"
#include "rayaccel/scene/import.h"

namespace rayaccel::exact {
namespace {

/// 1,024 rays from seeded origins one to three bunny sizes away, each aimed exactly at a vertex or at a point of an
/// edge (the float midpoint of its ends), direction = target - origin.
std::vector<Ray> edge_and_vertex_rays(const TriangleMesh& mesh) {
  conformance::Rng rng(1919);
  AABB box;
  for (const Vec3& v : mesh.vertices) box.extend(v);
  const float size = length(box.extent());
  std::vector<Ray> rays;
  while (rays.size() < 1024) {
    const auto& tri = mesh.triangles[rng.below(static_cast<std::uint32_t>(mesh.triangles.size()))];
    const std::uint32_t k = rng.below(3);
    const Vec3 a = mesh.vertices[tri[k]], b = mesh.vertices[tri[(k + 1) % 3]];
    const Vec3 target = rays.size() % 2 == 0 ? a : (a + b) * 0.5f;
    Ray ray;
    ray.origin = box.center() + rng.unit_vector() * (size * rng.uniform(1.0f, 3.0f));
    ray.direction = target - ray.origin;
    rays.push_back(ray);
  }
  return rays;
}

/// Counts of ray/triangle tests that get past the float early-out (edge functions surely of opposite signs) and,
/// of those, the ones whose edge functions lie inside their error bound or are ill-conditioned (the kernel then
/// recomputes them exactly: exact_edge.h); and the rays for which that happens at least once. Replays the scalar
/// kernel's decisions (ray_triangle.h) over every triangle, as brute force tests them.
struct BandCounts {
  std::size_t tests = 0, undecided = 0, in_band = 0, rays_in_band = 0;
};

BandCounts count_band_entries(const TriangleMesh& mesh, const std::vector<Ray>& rays) {
  BandCounts c;
  for (const Ray& ray : rays) {
    const PreparedRay r(ray);
    bool any = false;
    for (const auto& tri : mesh.triangles) {
      ++c.tests;
      const Vec3 a = mesh.vertices[tri[0]] - r.origin, b = mesh.vertices[tri[1]] - r.origin,
                 cc = mesh.vertices[tri[2]] - r.origin;
      const ShearedTriangle s{a[r.kx] - r.shear_x * a[r.kz], a[r.ky] - r.shear_y * a[r.kz], a[r.kz],
                              b[r.kx] - r.shear_x * b[r.kz], b[r.ky] - r.shear_y * b[r.kz], b[r.kz],
                              cc[r.kx] - r.shear_x * cc[r.kz], cc[r.ky] - r.shear_y * cc[r.kz], cc[r.kz]};
      const EdgeFunctions e(s);
      const TriangleErrorBounds bounds(r, s, 0.0f);
      if (e.surely_mixed(bounds.edge_error)) continue;
      ++c.undecided;
      const float det = (e.u + e.v) + e.w;
      if (e.in_band(bounds.edge_error) ||
          bounds.edge_error * WatertightBounds::kIllConditioned >= std::fabs(det)) {
        ++c.in_band;
        any = true;
      }
    }
    c.rays_in_band += any ? 1 : 0;
  }
  return c;
}

void print_band(const char* what, const BandCounts& c, std::size_t rays) {
  std::printf("[ band ] %s: %zu rays, %zu ray/triangle tests, %zu past the float early-out, %zu in the exact band "
              "(%.3g of tests, %.3g of undecided); rays entering the band: %zu (%.1f%%)\n",
              what, rays, c.tests, c.undecided, c.in_band, double(c.in_band) / double(c.tests),
              c.undecided ? double(c.in_band) / double(c.undecided) : 0.0, c.rays_in_band,
              100.0 * double(c.rays_in_band) / double(rays));
}

TEST(BunnyEdgeRays, BruteForceAndDefaultStructureAgreeWithExactArithmetic) {
  const auto file = testing::shared_scenes_dir() / "bunny.ply";
  RAYACCEL_NEED_SHARED_FILE(file);
  const TriangleMesh mesh = import_mesh(file);
  const Scene scene = Scene::from_mesh(mesh, "bunny");
  const ExactReference reference(mesh);
  const std::vector<Ray> rays = edge_and_vertex_rays(mesh);
  const auto exact = exact_hits(reference, rays);
  std::size_t exact_hit_rays = 0;
  for (const auto& h : exact) exact_hit_rays += h.empty() ? 0 : 1;
  EXPECT_GT(exact_hit_rays, 900u) << "rays aimed at the mesh mostly hit it";
  for (const char* spec : {"brute_force", "bvh_wide", "bvh"}) {
    auto accel = make_accelerator(spec);
    accel->build(scene);
    EXPECT_EQ(expect_exact_answers(*accel, rays, exact, std::string(spec) + " on bunny edge/vertex rays"), 0u);
  }

  // The band measurement: edge-aimed rays against ordinary camera rays of the same view distances.
  print_band("bunny, rays at edges and vertices", count_band_entries(mesh, rays), rays.size());
  std::vector<Ray> ordinary;
  conformance::Rng rng(2020);
  AABB box = scene.bounds();
  for (std::size_t i = 0; i < rays.size(); ++i) {
    Ray ray;
    ray.origin = box.center() + rng.unit_vector() * (length(box.extent()) * rng.uniform(1.0f, 3.0f));
    ray.direction = rng.in_box(box) - ray.origin;
    ordinary.push_back(ray);
  }
  print_band("bunny, ordinary rays into its box", count_band_entries(mesh, ordinary), ordinary.size());
}

}  // namespace
}  // namespace rayaccel::exact
