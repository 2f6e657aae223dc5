// Octree update cost against a full rebuild (Google Benchmark): removing and re-inserting k primitives of a
// 20,000-triangle soup, versus building the whole octree again. Figures only; the tests check correctness.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "rayaccel/accel/octree.h"

namespace rayaccel {
namespace {

const Scene& soup_scene() {
  static const Scene scene = [] {
    std::mt19937 rng(1234);
    std::uniform_real_distribution<float> pos(-1.0f, 1.0f), off(-0.02f, 0.02f);
    TriangleMesh m;
    for (std::uint32_t i = 0; i < 20000; ++i) {
      const Vec3 c{pos(rng), pos(rng), pos(rng)};
      for (int k = 0; k < 3; ++k) m.vertices.push_back(c + Vec3{off(rng), off(rng), off(rng)});
      m.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
    }
    return Scene::from_mesh(std::move(m), "soup20k");
  }();
  return scene;
}

void BM_OctreeRebuild(benchmark::State& state) {
  const Scene& scene = soup_scene();
  Octree tree;
  for (auto _ : state) {
    tree.build(scene);
    benchmark::DoNotOptimize(tree.active_count());
  }
  state.counters["primitives"] = scene.primitive_count();
}
BENCHMARK(BM_OctreeRebuild)->Unit(benchmark::kMillisecond);

/// One iteration removes state.range(0) random primitives and inserts them again (2k updates).
void BM_OctreeRemoveInsert(benchmark::State& state) {
  const Scene& scene = soup_scene();
  Octree tree;
  tree.build(scene);
  const auto k = std::size_t(state.range(0));
  std::mt19937 rng(99);
  std::vector<std::uint32_t> all(scene.primitive_count()), ids;
  for (std::uint32_t id = 0; id < all.size(); ++id) all[id] = id;
  for (auto _ : state) {
    state.PauseTiming();
    std::shuffle(all.begin(), all.end(), rng);
    ids.assign(all.begin(), all.begin() + std::ptrdiff_t(k));
    state.ResumeTiming();
    for (const std::uint32_t id : ids) tree.remove(id);
    for (const std::uint32_t id : ids) tree.insert(id);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(2 * k));
}
BENCHMARK(BM_OctreeRemoveInsert)->Arg(1)->Arg(64)->Arg(1024)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace rayaccel
