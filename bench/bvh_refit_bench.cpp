// Refit versus rebuild of a BVH over a 256x256-quad grid deformed by a wave (131,072 triangles): the cost of
// keeping a deforming mesh traceable per frame.
#include <benchmark/benchmark.h>

#include <cmath>

#include "rayaccel/bvh/bvh.h"

namespace rayaccel {
namespace {

struct WaveGrid {
  std::vector<Vec3> rest;
  Scene scene;

  explicit WaveGrid(std::uint32_t n) {
    TriangleMesh mesh;
    for (std::uint32_t j = 0; j <= n; ++j) {
      for (std::uint32_t i = 0; i <= n; ++i) {
        mesh.vertices.push_back({static_cast<float>(i) / static_cast<float>(n), 0.0f,
                                 static_cast<float>(j) / static_cast<float>(n)});
      }
    }
    for (std::uint32_t j = 0; j < n; ++j) {
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t a = j * (n + 1) + i;
        mesh.triangles.push_back({a, a + 1, a + n + 1});
        mesh.triangles.push_back({a + 1, a + n + 2, a + n + 1});
      }
    }
    rest = mesh.vertices;
    scene = Scene::from_mesh(std::move(mesh), "wave");
  }

  void frame(int f) {
    std::vector<Vec3> v = rest;
    const float phase = 0.3f * static_cast<float>(f);
    for (Vec3& p : v) p.y = 0.05f * std::sin(20.0f * p.x + phase) * std::cos(15.0f * p.z - phase);
    scene.set_vertices(v);
  }
};

void bvh_refit(benchmark::State& state, BvhBuilder builder) {
  WaveGrid grid(256);
  BvhOptions config;
  config.builder = builder;
  Bvh<AabbVolume> bvh(config);
  bvh.build(grid.scene);
  int f = 0;
  for (auto _ : state) {
    state.PauseTiming();
    grid.frame(++f);
    state.ResumeTiming();
    bvh.refit();
  }
}

void bvh_rebuild(benchmark::State& state, BvhBuilder builder) {
  WaveGrid grid(256);
  BvhOptions config;
  config.builder = builder;
  Bvh<AabbVolume> bvh(config);
  int f = 0;
  for (auto _ : state) {
    state.PauseTiming();
    grid.frame(++f);
    state.ResumeTiming();
    bvh.build(grid.scene);
  }
}

BENCHMARK_CAPTURE(bvh_refit, binned, BvhBuilder::binned)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(bvh_rebuild, binned, BvhBuilder::binned)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(bvh_rebuild, lbvh, BvhBuilder::lbvh)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace rayaccel
