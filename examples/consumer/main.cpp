// A program that uses rayaccel from outside: a scene over its own arrays, traced, the answers checked. The README's
// "Use it from your project" shows the part between the README markers; tests/package/consumers.cmake builds this
// file three ways (find_package, add_subdirectory, pkg-config), two of them with -ffast-math -ffp-contract=fast.
// Usage: consumer [RAYACCEL_CLI WORK_DIR]; with the CLI, rays aimed at edges must give the CLI's hits bit for bit.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "rayaccel/accel/registry.h"
#include "rayaccel/version.h"

namespace {

int failures = 0;

void check(bool ok, const std::string& what) {
  if (!ok) {
    std::fprintf(stderr, "FAILED: %s\n", what.c_str());
    ++failures;
  }
}

bool same_hit(const rayaccel::Hit& a, const rayaccel::Hit& b) { return std::memcmp(&a, &b, sizeof(a)) == 0; }

std::string describe(const rayaccel::Hit& h) {
  return "t=" + std::to_string(h.t) + " prim=" + std::to_string(h.prim_id) + " u=" + std::to_string(h.u) +
         " v=" + std::to_string(h.v);
}

template <typename T>
void put(std::ofstream& out, const T& value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(value));
}

/// Rays from random origins above and below a quad (vertices 0 1 2 3, diagonal 0-2), aimed at random points of its
/// edges (the shared diagonal most of all) and at its corners: where a kernel's rounding decides between hit, miss
/// and which side.
std::vector<rayaccel::Ray> edge_rays(const float* v) {
  std::mt19937 rng(25);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), spread(-3.0f, 3.0f);
  const int edges[5][2] = {{0, 2}, {0, 1}, {1, 2}, {2, 3}, {3, 0}};
  std::vector<rayaccel::Ray> rays;
  for (int i = 0; i < 2000; ++i) {
    const int* e = edges[i % 10 < 6 ? 0 : 1 + i % 4];
    const float s = i % 50 == 0 ? 0.0f : unit(rng);  // some rays at a corner exactly
    rayaccel::Vec3 target;
    for (int a = 0; a < 3; ++a) target[a] = v[3 * e[0] + a] + s * (v[3 * e[1] + a] - v[3 * e[0] + a]);
    const rayaccel::Vec3 origin{spread(rng), spread(rng), (i % 2 ? 1.0f : -1.0f) * (0.5f + 2 * unit(rng))};
    rays.push_back(rayaccel::Ray{origin, 0.0f, target - origin, 10.0f});
  }
  return rays;
}

/// Writes the quad as a binary PLY and the rays as a .rays file for the CLI.
void write_inputs(const std::string& dir, const float* vertices, const std::uint32_t* indices,
                  const std::vector<rayaccel::Ray>& rays) {
  std::ofstream ply(dir + "/quad.ply", std::ios::binary);
  ply << "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
         "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < 12; ++i) put(ply, vertices[i]);
  for (int t = 0; t < 2; ++t) {
    put(ply, std::uint8_t{3});
    for (int k = 0; k < 3; ++k) put(ply, static_cast<std::int32_t>(indices[3 * t + k]));
  }
  std::ofstream out(dir + "/edges.rays", std::ios::binary);
  for (const rayaccel::Ray& r : rays) {
    for (float f : {r.origin.x, r.origin.y, r.origin.z, r.t_min, r.direction.x, r.direction.y, r.direction.z,
                    r.t_max}) {
      put(out, f);
    }
  }
}

/// Runs `rayaccel trace --accel SPEC` on the files write_inputs() wrote and reads its .hits back (empty when the
/// CLI fails or writes too little).
std::vector<rayaccel::Hit> cli_hits(const std::string& cli, const std::string& dir, const std::string& spec,
                                    std::size_t count) {
  const std::string hits_file = dir + "/" + spec + ".hits";
  const std::string command = "'" + cli + "' trace '" + dir + "/quad.ply' '" + dir + "/edges.rays' --accel " + spec +
                              " --repeat 1 --out '" + hits_file + "' > '" + dir + "/" + spec + ".log'";
  if (std::system(command.c_str()) != 0) {
    std::fprintf(stderr, "FAILED: %s\n", command.c_str());
    return {};
  }
  std::vector<rayaccel::Hit> hits(count);
  std::ifstream in(hits_file, std::ios::binary);
  in.read(reinterpret_cast<char*>(hits.data()), static_cast<std::streamsize>(count * sizeof(rayaccel::Hit)));
  if (in.gcount() != static_cast<std::streamsize>(count * sizeof(rayaccel::Hit))) return {};
  return hits;
}

}  // namespace

int main(int argc, char** argv) {
  std::printf("rayaccel %s\n", RAYACCEL_VERSION_STRING);

  // README: begin
  // Two triangles over the unit square in the plane z = 0, sharing the edge from (0,0,0) to (1,1,0).
  const float vertices[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};  // x y z per vertex
  const std::uint32_t indices[] = {0, 1, 2, 0, 2, 3};           // three per triangle
  rayaccel::MeshBuffers buffers;
  buffers.vertices = vertices;
  buffers.vertex_count = 4;
  buffers.indices = indices;
  buffers.triangle_count = 2;
  rayaccel::Scene scene = rayaccel::Scene::from_buffers(buffers);  // reads the arrays in place: keep them alive
  auto accel = rayaccel::make_accelerator("bvh_wide");
  accel->build(scene);
  rayaccel::Ray ray{{0.25f, 0.5f, 1}, 0.0f, {0, 0, -1}, 10.0f};  // origin, t_min, direction, t_max
  rayaccel::Hit hit = accel->intersect(ray);                     // t = 1 on triangle 1 at (0.25, 0.5, 0)
  // README: end
  check(hit.t == 1.0f && hit.prim_id == 1, "the README ray: " + describe(hit));
  check(!accel->occluded(rayaccel::Ray{{2, 2, 1}, 0.0f, {0, 0, -1}, 10.0f}), "a ray beside the square is occluded");

  // The same quad interleaved with normals (24-byte vertices) and with uint16 indices: the same answers.
  const float interleaved[] = {0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 1, 0, 0, 0, 1, 0, 1, 0, 0, 0, 1};
  const std::uint16_t narrow[] = {0, 1, 2, 0, 2, 3};
  rayaccel::MeshBuffers strided;
  strided.vertices = interleaved;
  strided.vertex_count = 4;
  strided.vertex_stride = 6 * sizeof(float);
  strided.indices = narrow;
  strided.triangle_count = 2;
  strided.index_type = rayaccel::IndexType::uint16;
  const rayaccel::Scene strided_scene = rayaccel::Scene::from_buffers(strided);
  auto brute = rayaccel::make_accelerator("brute_force");
  brute->build(scene);
  auto brute_strided = rayaccel::make_accelerator("brute_force");
  brute_strided->build(strided_scene);

  // Rays at edges of the square: every ray through its shared diagonal hits one of the two triangles; brute force
  // gives the same bits over both buffer layouts; the wide BVH finds the same hits (t within 1e-6: structures may
  // break ties on an edge differently).
  std::vector<rayaccel::Ray> rays = edge_rays(vertices);
  std::vector<rayaccel::Hit> wide(rays.size()), exact(rays.size()), strided_exact(rays.size());
  accel->intersect(rays, wide);
  brute->intersect(rays, exact);
  brute_strided->intersect(rays, strided_exact);
  int diagonal_misses = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const std::string name = "ray " + std::to_string(i) + ": ";
    check(same_hit(exact[i], strided_exact[i]),
          name + "brute force " + describe(exact[i]) + ", over uint16 strided buffers " + describe(strided_exact[i]));
    check(wide[i].found() == exact[i].found() &&
              (!exact[i].found() || std::fabs(wide[i].t - exact[i].t) <= 1e-6f * exact[i].t),
          name + "bvh_wide " + describe(wide[i]) + ", brute force " + describe(exact[i]));
    if (i % 10 < 6 && i % 50 != 0 && !(exact[i].found() && wide[i].found())) ++diagonal_misses;
  }
  check(diagonal_misses == 0, std::to_string(diagonal_misses) + " rays through the shared edge missed both sides");

  // Given the CLI: a folded quad with coordinates that round in every product, traced here (code compiled with this
  // program's flags around it) and by the CLI, must give the same hits bit for bit, structure by structure.
  if (argc == 3) {
    const float folded[] = {0.1f, 0.2f, 0.3f, 1.7f, -0.4f, 0.9f, 1.3f, 1.1f, -0.2f, -0.3f, 0.9f, 0.7f};
    rayaccel::MeshBuffers folded_buffers = buffers;
    folded_buffers.vertices = folded;
    const rayaccel::Scene folded_scene = rayaccel::Scene::from_buffers(folded_buffers, "folded");
    accel->build(folded_scene);
    brute->build(folded_scene);
    rays = edge_rays(folded);
    accel->intersect(rays, wide);
    brute->intersect(rays, exact);
    std::size_t folded_hits = 0;
    for (const rayaccel::Hit& h : exact) folded_hits += h.found() ? 1 : 0;
    check(folded_hits > rays.size() / 4, "only " + std::to_string(folded_hits) + " edge rays hit the folded quad");
    write_inputs(argv[2], folded, indices, rays);
    for (const auto& [spec, ours] : {std::pair{"brute_force", &exact}, std::pair{"bvh_wide", &wide}}) {
      const std::vector<rayaccel::Hit> cli = cli_hits(argv[1], argv[2], spec, rays.size());
      check(cli.size() == rays.size(), std::string("the CLI wrote no hits with ") + spec);
      for (std::size_t i = 0; i < cli.size(); ++i) {
        check(same_hit((*ours)[i], cli[i]), std::string(spec) + " ray " + std::to_string(i) + ": here " +
                                                describe((*ours)[i]) + ", CLI " + describe(cli[i]));
      }
    }
  }
  std::printf("%s: %zu edge rays, %d failures\n", failures ? "FAILED" : "ok", rays.size(), failures);
  return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
