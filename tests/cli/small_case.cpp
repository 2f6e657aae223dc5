// The CLI tests' small case (see small_case.h).
#include "small_case.h"

#include <cstdint>
#include <fstream>
#include <random>

#include "cli_runner.h"
#include "rayaccel/scene/ray_io.h"

namespace rayaccel::testing {

TriangleMesh small_mesh() {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  TriangleMesh mesh;
  for (std::uint32_t i = 0; i < 300; ++i) {
    const Vec3 center{u(rng), u(rng), u(rng)};
    for (int k = 0; k < 3; ++k) mesh.vertices.push_back(center + Vec3{u(rng), u(rng), u(rng)} * 0.25f);
    mesh.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  mesh.triangles.push_back(mesh.triangles[5]);
  const auto n = static_cast<std::uint32_t>(mesh.vertices.size());
  mesh.vertices.push_back({0.0f, 0.0f, 0.0f});
  mesh.vertices.push_back({1.0f, 1.0f, 1.0f});
  mesh.vertices.push_back({2.0f, 2.0f, 2.0f});
  mesh.triangles.push_back({n, n + 1, n + 2});
  return mesh;
}

std::vector<Ray> small_rays(const TriangleMesh& mesh) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  std::uniform_int_distribution<std::size_t> pick(0, mesh.triangles.size() - 1);
  std::vector<Ray> rays;
  for (int i = 0; i < 600; ++i) {
    Ray r;
    r.origin = {u(rng), u(rng), u(rng)};
    if (i % 5 == 4) {
      r.direction = {u(rng), u(rng), u(rng)};
    } else {
      const auto& t = mesh.triangles[pick(rng)];
      const Vec3 target = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) * (1.0f / 3.0f);
      r.direction = target - r.origin;
    }
    if (i % 7 == 3) r.t_max = 0.6f;
    if (i % 11 == 2) r.t_min = 0.4f;
    rays.push_back(r);
  }
  return rays;
}

SmallCase make_small_case() {
  SmallCase c;
  c.dir = fresh_directory("case");
  c.ply = c.dir / "small.ply";
  c.rays = c.dir / "small.rays";
  c.mesh = small_mesh();
  write_ply(c.ply, c.mesh);
  write_rays(c.rays, small_rays(c.mesh));
  return c;
}

}  // namespace rayaccel::testing
