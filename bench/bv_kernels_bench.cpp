// Micro-benchmarks of the bounding volumes' ray tests (per ray-volume pair, the per-ray context made once per ray as
// traversal does), of the watertight triangle test for scale, of the k-DOP per-ray setup, and of fitting.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "rayaccel/bv/aabb_volume.h"
#include "rayaccel/bv/kdop_volume.h"
#include "rayaccel/bv/obb_volume.h"
#include "rayaccel/bv/sphere_volume.h"
#include "rayaccel/geometry/ray_triangle.h"

namespace rayaccel {
namespace {

constexpr int kRayCount = 256;
constexpr int kNodeCount = 64;

Vec3 random_vec(std::mt19937& rng, float lo, float hi) {
  std::uniform_real_distribution<float> u(lo, hi);
  return {u(rng), u(rng), u(rng)};
}

/// Rays from a surrounding box toward random points of the unit cube: roughly half of them hit a given node.
std::vector<Ray> make_rays() {
  std::mt19937 rng(1);
  std::vector<Ray> rays;
  for (int i = 0; i < kRayCount; ++i) {
    const Vec3 o = random_vec(rng, -3.0f, 3.0f);
    rays.push_back(Ray{o, 0.0f, random_vec(rng, -0.5f, 0.5f) - o, 1e30f});
  }
  return rays;
}

/// Node-like point sets: 12 triangles of a small cluster each, spread over the unit cube.
std::vector<std::vector<Vec3>> make_point_sets() {
  std::mt19937 rng(2);
  std::vector<std::vector<Vec3>> sets;
  for (int n = 0; n < kNodeCount; ++n) {
    const Vec3 c = random_vec(rng, -0.6f, 0.6f);
    std::vector<Vec3> pts;
    for (int i = 0; i < 36; ++i) pts.push_back(c + random_vec(rng, -0.4f, 0.4f));
    sets.push_back(std::move(pts));
  }
  return sets;
}

template <class BV>
void BM_VolumeRayTest(benchmark::State& state) {
  std::vector<PreparedRay> rays;
  for (const Ray& r : make_rays()) rays.emplace_back(r);
  std::vector<BV> nodes;
  for (const auto& pts : make_point_sets()) nodes.push_back(BV::fit(pts));
  int hits = 0;
  for (auto _ : state) {
    for (const PreparedRay& ray : rays) {
      const typename BV::RayContext ctx = BV::prepare(ray);
      for (const BV& node : nodes) {
        float entry = 0.0f;
        hits += node.intersect(ctx, ray.t_min, ray.t_max, &entry) ? 1 : 0;
        benchmark::DoNotOptimize(entry);
      }
    }
  }
  state.SetItemsProcessed(state.iterations() * kRayCount * kNodeCount);
  state.counters["hit_rate"] = double(hits) / double(state.iterations() * kRayCount * kNodeCount);
  state.counters["ns_per_test"] = benchmark::Counter(double(state.iterations() * kRayCount * kNodeCount),
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_VolumeRayTest<AabbVolume>)->Name("ray_test/aabb");
BENCHMARK(BM_VolumeRayTest<SphereVolume>)->Name("ray_test/sphere");
BENCHMARK(BM_VolumeRayTest<ObbVolume>)->Name("ray_test/obb");
BENCHMARK(BM_VolumeRayTest<Kdop14Volume>)->Name("ray_test/kdop14");
BENCHMARK(BM_VolumeRayTest<Kdop18Volume>)->Name("ray_test/kdop18");
BENCHMARK(BM_VolumeRayTest<Kdop26Volume>)->Name("ray_test/kdop26");

void BM_TriangleTest(benchmark::State& state) {
  std::vector<PreparedRay> rays;
  for (const Ray& r : make_rays()) rays.emplace_back(r);
  std::vector<std::array<Vec3, 3>> tris;
  for (const auto& pts : make_point_sets()) tris.push_back({pts[0], pts[1], pts[2]});
  int hits = 0;
  for (auto _ : state) {
    for (const PreparedRay& ray : rays) {
      Hit hit = Hit::begin(ray);
      for (const auto& t : tris) hits += intersect_triangle(ray, t[0], t[1], t[2], 0, hit) ? 1 : 0;
      benchmark::DoNotOptimize(hit);
    }
  }
  state.SetItemsProcessed(state.iterations() * kRayCount * kNodeCount);
  state.counters["hit_rate"] = double(hits) / double(state.iterations() * kRayCount * kNodeCount);
  state.counters["ns_per_test"] = benchmark::Counter(double(state.iterations() * kRayCount * kNodeCount),
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_TriangleTest)->Name("ray_test/triangle");

template <class BV>
void BM_Prepare(benchmark::State& state) {
  std::vector<PreparedRay> rays;
  for (const Ray& r : make_rays()) rays.emplace_back(r);
  for (auto _ : state) {
    for (const PreparedRay& ray : rays) {
      typename BV::RayContext ctx = BV::prepare(ray);
      benchmark::DoNotOptimize(ctx);
    }
  }
  state.SetItemsProcessed(state.iterations() * kRayCount);
}
BENCHMARK(BM_Prepare<Kdop14Volume>)->Name("prepare/kdop14");
BENCHMARK(BM_Prepare<Kdop26Volume>)->Name("prepare/kdop26");

template <class BV>
void BM_Fit(benchmark::State& state) {
  std::mt19937 rng(3);
  std::vector<Vec3> pts;
  for (int i = 0; i < state.range(0); ++i) pts.push_back(random_vec(rng, -1.0f, 1.0f));
  for (auto _ : state) {
    BV v = BV::fit(pts);
    benchmark::DoNotOptimize(v);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_Fit<AabbVolume>)->Name("fit/aabb")->Arg(3)->Arg(36)->Arg(3000);
BENCHMARK(BM_Fit<SphereVolume>)->Name("fit/sphere")->Arg(3)->Arg(36)->Arg(3000);
BENCHMARK(BM_Fit<ObbVolume>)->Name("fit/obb")->Arg(3)->Arg(36)->Arg(3000);
BENCHMARK(BM_Fit<Kdop26Volume>)->Name("fit/kdop26")->Arg(3)->Arg(36)->Arg(3000);

void BM_KdopArea(benchmark::State& state) {
  const Kdop26Volume v = Kdop26Volume::fit(make_point_sets()[0]);
  for (auto _ : state) benchmark::DoNotOptimize(v.surface_area());
}
BENCHMARK(BM_KdopArea)->Name("surface_area/kdop26");

}  // namespace
}  // namespace rayaccel

BENCHMARK_MAIN();
