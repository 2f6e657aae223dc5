// The independent check of the whole pipeline: `rayaccel trace --accel brute_force` on the Stanford bunny must
// write the same bytes as tests/reference/reference_trace.py, a numpy tracer written from the watertight-test
// paper (Woop, Benthin, Wald 2013) with its own PLY reader, for camera rays and adversarial random rays.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "../cli/cli_runner.h"
#include "../shared_scenes.h"
#include "rayaccel/render/camera.h"
#include "rayaccel/scene/import.h"
#include "rayaccel/scene/ray_io.h"
#include "../test_paths.h"

namespace rayaccel {
namespace {

/// 1024 camera rays of the standard camera, then rays aimed exactly at vertices (edge and vertex cases), at
/// centroids with t_min/t_max limits around the hit, from points on the surface, along axes with +-0 components,
/// in random directions, and a few void rays.
std::vector<Ray> bunny_rays(const std::filesystem::path& ply, const TriangleMesh& mesh) {
  std::vector<Ray> rays;
  const auto camera = standard_camera(ply);
  EXPECT_TRUE(camera.has_value()) << "the MANIFEST should give the bunny a standard camera";
  if (camera) {
    for (int y = 0; y < 32; ++y) {
      for (int x = 0; x < 32; ++x) rays.push_back(camera->primary_ray(x, y, 32, 32));
    }
  }
  AABB box;
  for (const Vec3& v : mesh.vertices) box.extend(v);
  const Vec3 center = box.center(), extent = box.extent();
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_int_distribution<std::size_t> pick_vertex(0, mesh.vertices.size() - 1);
  std::uniform_int_distribution<std::size_t> pick_triangle(0, mesh.triangles.size() - 1);
  const auto outside = [&] { return center + Vec3{unit(rng), unit(rng), unit(rng)} * extent * 1.5f; };
  const auto centroid = [&](std::size_t t) {
    const auto& tri = mesh.triangles[t];
    return (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) * (1.0f / 3.0f);
  };
  for (int i = 0; i < 300; ++i) {  // through a vertex: the ray runs exactly over shared edges
    Ray r;
    r.origin = outside();
    r.direction = mesh.vertices[pick_vertex(rng)] - r.origin;
    rays.push_back(r);
  }
  const float limits[] = {0.5f, 0.999f, 1.0f, 1.001f};
  for (int i = 0; i < 300; ++i) {  // toward a centroid (t = 1) with the interval ending or starting near the hit
    Ray r;
    r.origin = outside();
    r.direction = centroid(pick_triangle(rng)) - r.origin;
    if (i % 2 == 0) {
      r.t_max = limits[i / 2 % 4];
    } else {
      r.t_min = limits[i / 2 % 4];
    }
    rays.push_back(r);
  }
  for (int i = 0; i < 150; ++i) {  // from a point on the surface
    Ray r;
    r.origin = centroid(pick_triangle(rng));
    r.direction = {unit(rng), unit(rng), unit(rng)};
    r.t_min = i % 3 == 0 ? 1e-4f : 0.0f;
    rays.push_back(r);
  }
  for (int i = 0; i < 150; ++i) {  // axis-aligned, with +0 and -0 components
    Ray r;
    const Vec3 target = centroid(pick_triangle(rng));
    const int axis = i % 3;
    r.origin = target;
    r.origin[axis] = i % 2 ? box.lo[axis] - 0.1f : box.hi[axis] + 0.1f;
    r.direction = Vec3{i % 4 < 2 ? 0.0f : -0.0f};
    r.direction[axis] = i % 2 ? 1.0f : -1.0f;
    rays.push_back(r);
  }
  for (int i = 0; i < 100; ++i) {  // anywhere, anyhow, including long unnormalized directions
    Ray r;
    r.origin = outside();
    r.direction = Vec3{unit(rng), unit(rng), unit(rng)} * (i % 2 ? 1000.0f : 0.001f);
    rays.push_back(r);
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  rays.push_back({{nan, 0.0f, 0.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, 1e30f});
  rays.push_back({center, 0.0f, {0.0f, 0.0f, 0.0f}, 1e30f});
  rays.push_back({outside(), 0.0f, center, 0.0f});
  rays.push_back({outside(), 2.0f, center, 1.0f});
  return rays;
}

TEST(SlowReference, BunnyBruteForceMatchesIndependentReference) {
  const std::filesystem::path ply = testing::shared_scenes_dir() / "bunny.ply";
  const std::filesystem::path script =
      std::filesystem::path(testing::source_dir()) / "tests" / "reference" / "reference_trace.py";
  RAYACCEL_NEED_SHARED_FILE(ply);
  RAYACCEL_NEED_SHARED_FILE(testing::shared_scenes_dir() / "MANIFEST.md");  // the standard camera
  // Not skipped when missing: scripts/setup.sh installs python3-numpy, so its absence is a broken setup.
  if (testing::run_program("/usr/bin/python3", {"-c", "import numpy"}).exit_code != 0) {
    FAIL() << "/usr/bin/python3 with numpy (Debian python3-numpy, installed by scripts/setup.sh) is needed for the "
              "reference tracer";
  }
  const std::filesystem::path dir = testing::fresh_directory("bunny");
  const std::vector<Ray> rays = bunny_rays(ply, import_mesh(ply));
  ASSERT_GE(rays.size(), 2000u);
  write_rays(dir / "bunny.rays", rays);

  const auto ours = testing::run_cli({"trace", ply.string(), (dir / "bunny.rays").string(), "--accel", "brute_force",
                                      "--repeat", "1", "--out", (dir / "cli.hits").string()});
  ASSERT_EQ(ours.exit_code, 0) << ours.err;
  // numpy allocates and frees many 280 KB temporaries per ray; raising glibc's mmap threshold keeps them on the
  // heap instead of mapping and unmapping each one (about 4x less time, almost all of it system time).
  const auto reference = testing::run_program(
      "/usr/bin/env", {"MALLOC_MMAP_THRESHOLD_=33554432", "MALLOC_TRIM_THRESHOLD_=268435456", "/usr/bin/python3",
                       script.string(), ply.string(), (dir / "bunny.rays").string(), (dir / "ref.hits").string()});
  ASSERT_EQ(reference.exit_code, 0) << reference.err;

  const std::vector<Hit> got = read_hits(dir / "cli.hits");
  const std::vector<Hit> want = read_hits(dir / "ref.hits");
  ASSERT_EQ(got.size(), rays.size());
  ASSERT_EQ(want.size(), rays.size());
  std::size_t differing = 0, hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    hits += want[i].found() ? 1 : 0;
    if (std::memcmp(&got[i], &want[i], sizeof(Hit)) == 0) continue;
    if (++differing <= 10) {
      ADD_FAILURE() << "ray " << i << ": rayaccel t=" << got[i].t << " prim=" << got[i].prim_id << " u=" << got[i].u
                    << " v=" << got[i].v << "; reference t=" << want[i].t << " prim=" << want[i].prim_id
                    << " u=" << want[i].u << " v=" << want[i].v;
    }
  }
  EXPECT_EQ(differing, 0u);
  EXPECT_EQ(testing::read_file(dir / "cli.hits"), testing::read_file(dir / "ref.hits")) << "files differ in bytes";
  EXPECT_GT(hits, rays.size() / 3) << "the ray set should mostly hit the bunny";
}

}  // namespace
}  // namespace rayaccel
