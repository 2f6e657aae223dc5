// Micro-benchmarks of the wide BVH's kernels: one ray against the 4 or 8 child boxes of a node (SSE, AVX2), against
// 4 or 8 triangles (Triangle4 block with SSE, two blocks with AVX2), and one triangle against a packet's 8 rays. Time per call; the per-ray constants are
// made once per ray, as traversal does.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "rayaccel/simd/box_kernel.h"
#include "rayaccel/simd/isa.h"
#if RAYACCEL_AVX_KERNELS
#include "rayaccel/simd/lanes_avx2.h"
#endif
#include "rayaccel/simd/watertight_lanes.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel::wide {
namespace {

#if RAYACCEL_AVX_KERNELS
using simd::Avx8;
#endif
using simd::Sse4;
using simd::cpu_has_avx2;
using BoxKernel4 = simd::BoxKernel<Sse4>;
#if RAYACCEL_AVX_KERNELS
using BoxKernel8 = simd::BoxKernel<Avx8>;
#endif

constexpr int kRays = 256;
constexpr int kItems = 64;

float uniform(std::mt19937& rng, float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }

std::vector<PreparedRay> make_rays() {
  std::mt19937 rng(1);
  std::vector<PreparedRay> rays;
  for (int i = 0; i < kRays; ++i) {
    const Vec3 o{uniform(rng, -3, 3), uniform(rng, -3, 3), uniform(rng, -3, 3)};
    const Vec3 target{uniform(rng, -0.5f, 0.5f), uniform(rng, -0.5f, 0.5f), uniform(rng, -0.5f, 0.5f)};
    rays.emplace_back(Ray{o, 0.0f, target - o, 1e30f});
  }
  return rays;
}

template <int W>
std::vector<Node<W>> make_nodes() {
  std::mt19937 rng(2);
  std::vector<Node<W>> nodes(kItems);
  for (auto& node : nodes) {
    for (int lane = 0; lane < W; ++lane) {
      for (int a = 0; a < 3; ++a) {
        const float c = uniform(rng, -1, 1), h = uniform(rng, 0.05f, 0.4f);
        node.bounds[a][0][lane] = c - h;
        node.bounds[a][1][lane] = c + h;
      }
      node.child[lane] = static_cast<std::uint32_t>(lane);
    }
  }
  return nodes;
}

std::vector<simd::Triangle4> make_blocks() {
  std::mt19937 rng(3);
  std::vector<simd::Triangle4> blocks(kItems);
  std::uint32_t id = 0;
  for (auto& b : blocks) {
    for (int lane = 0; lane < 4; ++lane) {
      const Vec3 c{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
      for (int v = 0; v < 3; ++v) {
        for (int a = 0; a < 3; ++a) b.vertex[v][a][lane] = c[a] + uniform(rng, -0.3f, 0.3f);
      }
      b.prim_id[lane] = id++;
    }
  }
  return blocks;
}

void BM_BoxKernel4(benchmark::State& state) {
  const auto rays = make_rays();
  const auto nodes = make_nodes<4>();
  alignas(32) float entry[4];
  std::size_t i = 0;
  for (auto _ : state) {
    const PreparedRay& r = rays[i % kRays];
    const BoxKernel4::Packet p = BoxKernel4::prepare(r);
    int hits = 0;
    for (const auto& node : nodes) hits += BoxKernel4::intersect(p, node, 1e30f, entry);
    benchmark::DoNotOptimize(hits);
    ++i;
  }
  state.SetItemsProcessed(state.iterations() * kItems);
}
BENCHMARK(BM_BoxKernel4);

#if RAYACCEL_AVX_KERNELS  // (simd/isa.h: a Clang build has only the SSE kernels)
RAYACCEL_TARGET_AVX2 __attribute__((flatten)) int box8_pass(const PreparedRay& r, const std::vector<Node<8>>& nodes) {
  alignas(32) float entry[8];
  const BoxKernel8::Packet p = BoxKernel8::prepare(r);
  int hits = 0;
  for (const auto& node : nodes) hits += BoxKernel8::intersect(p, node, 1e30f, entry);
  return hits;
}

void BM_BoxKernel8(benchmark::State& state) {
  if (!cpu_has_avx2()) return state.SkipWithError("no AVX2 on this CPU");
  const auto rays = make_rays();
  const auto nodes = make_nodes<8>();
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(box8_pass(rays[i++ % kRays], nodes));
  state.SetItemsProcessed(state.iterations() * kItems);
}
BENCHMARK(BM_BoxKernel8);
#endif

void BM_TriangleLanes4(benchmark::State& state) {
  const auto rays = make_rays();
  const auto blocks = make_blocks();
  std::size_t i = 0;
  for (auto _ : state) {
    const PreparedRay& r = rays[i++ % kRays];
    const simd::TrianglePacket<Sse4> p(r);
    Hit hit = Hit::begin(r);
    for (const auto& b : blocks) intersect_triangles4(p, r, b, hit);
    benchmark::DoNotOptimize(hit);
  }
  state.SetItemsProcessed(state.iterations() * kItems);  // blocks of 4 triangles
}
BENCHMARK(BM_TriangleLanes4);

#if RAYACCEL_AVX_KERNELS
RAYACCEL_TARGET_AVX2 __attribute__((flatten)) Hit triangles8_pass(const PreparedRay& r,
                                                               const std::vector<simd::Triangle4>& blocks) {
  const simd::TrianglePacket<Avx8> p(r);
  Hit hit = Hit::begin(r);
  for (std::size_t b = 0; b + 1 < blocks.size(); b += 2) {
    const simd::Triangle4* pair[2] = {&blocks[b], &blocks[b + 1]};
    intersect_triangle_lanes<Avx8>(p, r, pair, hit);
  }
  return hit;
}

void BM_TriangleLanes8(benchmark::State& state) {
  if (!cpu_has_avx2()) return state.SkipWithError("no AVX2 on this CPU");
  const auto rays = make_rays();
  const auto blocks = make_blocks();
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(triangles8_pass(rays[i++ % kRays], blocks));
  state.SetItemsProcessed(state.iterations() * kItems);  // blocks of 4 triangles, tested two at a time
}
BENCHMARK(BM_TriangleLanes8);
#endif

#if RAYACCEL_AVX_KERNELS
/// Eight coherent rays (one origin, targets around the triangles; all with the same axes kx, ky, kz) with the
/// packet's per-lane constants, as the packet traversal holds them.
std::vector<Ray> make_coherent_rays() {
  std::mt19937 rng(4);
  std::vector<Ray> rays;
  for (int i = 0; i < 8 * kRays; ++i) {
    const Vec3 o{0.1f, -0.2f, 3.0f};
    const Vec3 target{uniform(rng, -0.5f, 0.5f), uniform(rng, -0.5f, 0.5f), uniform(rng, -0.5f, 0.5f)};
    rays.push_back({o, 0.0f, target - o, 1e30f});
  }
  return rays;
}

RAYACCEL_TARGET_AVX2 __attribute__((flatten)) int triangle_rays_pass(const Ray* rays,
                                                                 const std::vector<simd::Triangle4>& blocks) {
  alignas(32) float lane[9][8];
  const PreparedRay first(rays[0]);
  const int axes[3] = {first.kx, first.ky, first.kz};
  Hit hits[8];
  for (int i = 0; i < 8; ++i) {
    const PreparedRay r(rays[i]);
    for (int a = 0; a < 3; ++a) lane[a][i] = r.origin[axes[a]];
    lane[3][i] = r.shear_x;
    lane[4][i] = r.shear_y;
    lane[5][i] = r.shear_z;
    lane[6][i] = r.t_min;
    lane[7][i] = shear_error(r.shear_x);
    lane[8][i] = shear_error(r.shear_y);
    hits[i] = Hit::begin(r);
  }
  simd::TrianglePacket<Avx8> p;
  for (int a = 0; a < 3; ++a) p.origin_k[a] = Avx8::load(lane[a]);
  p.shear_x = Avx8::load(lane[3]);
  p.shear_y = Avx8::load(lane[4]);
  p.shear_z = Avx8::load(lane[5]);
  p.t_min = Avx8::load(lane[6]);
  p.shear_error_x = Avx8::load(lane[7]);
  p.shear_error_y = Avx8::load(lane[8]);
  alignas(32) float far[8];
  for (int i = 0; i < 8; ++i) far[i] = hits[i].t;
  __m256 t_far = Avx8::load(far);
  int updated = 0;
  for (const auto& b : blocks) {
    for (int j = 0; j < 4; ++j) updated |= intersect_triangle_rays<Avx8>(p, rays, 0xFF, axes, b, j, hits, t_far);
  }
  return updated;
}

void BM_TriangleRays8(benchmark::State& state) {
  if (!cpu_has_avx2()) return state.SkipWithError("no AVX2 on this CPU");
  const auto rays = make_coherent_rays();
  const auto blocks = make_blocks();
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(triangle_rays_pass(&rays[8 * (i++ % kRays)], blocks));
  // Items as above (four ray-triangle tests each): every block against eight rays, one triangle at a time.
  state.SetItemsProcessed(state.iterations() * kItems * 8);
}
BENCHMARK(BM_TriangleRays8);
#endif

}  // namespace
}  // namespace rayaccel::wide
