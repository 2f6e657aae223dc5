// Micro-benchmarks of the bounding volumes' ray tests (per ray-volume pair, the per-ray context made once per ray as
// traversal does), of the watertight triangle test for scale, of the k-DOP per-ray setup and of fitting; plus the
// volumes' tightness on typical point sets, reported as counters.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "rayaccel/bv/aabb_volume.h"
#include "rayaccel/bv/capsule_volume.h"
#include "rayaccel/bv/hull_volume.h"
#include "rayaccel/bv/kdop_volume.h"
#include "rayaccel/bv/obb_volume.h"
#include "rayaccel/bv/sphere_volume.h"
#include "rayaccel/bv/tightness.h"
#include "rayaccel/bvh/bvh.h"
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
  state.counters["bytes_per_node"] = double(sizeof(BvhNode<BV>));
}
BENCHMARK(BM_VolumeRayTest<AabbVolume>)->Name("ray_test/aabb");
BENCHMARK(BM_VolumeRayTest<SphereVolume>)->Name("ray_test/sphere");
BENCHMARK(BM_VolumeRayTest<ObbVolume>)->Name("ray_test/obb");
BENCHMARK(BM_VolumeRayTest<Kdop14Volume>)->Name("ray_test/kdop14");
BENCHMARK(BM_VolumeRayTest<Kdop18Volume>)->Name("ray_test/kdop18");
BENCHMARK(BM_VolumeRayTest<Kdop26Volume>)->Name("ray_test/kdop26");
BENCHMARK(BM_VolumeRayTest<HullVolume>)->Name("ray_test/hull");
BENCHMARK(BM_VolumeRayTest<CapsuleVolume>)->Name("ray_test/capsule");

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
BENCHMARK(BM_Fit<HullVolume>)->Name("fit/hull")->Arg(3)->Arg(36)->Arg(3000);
BENCHMARK(BM_Fit<CapsuleVolume>)->Name("fit/capsule")->Arg(3)->Arg(36)->Arg(3000);

void BM_KdopArea(benchmark::State& state) {
  const Kdop26Volume v = Kdop26Volume::fit(make_point_sets()[0]);
  for (auto _ : state) benchmark::DoNotOptimize(v.surface_area());
}
BENCHMARK(BM_KdopArea)->Name("surface_area/kdop26");

/// Point sets of a given shape: 0 random in a cube, 1 a 30-degree cap of a sphere surface (a typical mesh node),
/// 2 a thin rotated sliver, 3 a whole sphere surface (a root node).
std::vector<std::vector<Vec3>> shape_sets(int shape) {
  std::mt19937 rng(4);
  std::normal_distribution<float> g;
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<std::vector<Vec3>> sets;
  for (int n = 0; n < 16; ++n) {
    const Vec3 axis = normalize(Vec3{g(rng), g(rng), g(rng)});
    std::vector<Vec3> pts;
    while (pts.size() < 60) {
      const Vec3 s = normalize(Vec3{g(rng), g(rng), g(rng)});
      if (shape == 0) pts.push_back({u(rng), u(rng), u(rng)});
      if (shape == 1 && dot(s, axis) > 0.866f) pts.push_back(s);
      if (shape == 2) pts.push_back(axis * (4.0f * u(rng)) + s * 0.05f);
      if (shape == 3) pts.push_back(s);
    }
    sets.push_back(std::move(pts));
  }
  return sets;
}

/// Tightness figures (not timings): mean area over mean AABB area and over mean convex hull area.
template <class BV>
void BM_Tightness(benchmark::State& state) {
  TightnessSums sums;
  for (auto _ : state) {
    sums = {};
    for (const auto& pts : shape_sets(int(state.range(0)))) sums.add(BV::fit(pts).surface_area(), pts);
  }
  state.counters["area_over_aabb"] = sums.over_aabb();
  state.counters["area_over_hull"] = sums.over_hull();
}
#define RAYACCEL_TIGHTNESS(BV, name) \
  BENCHMARK(BM_Tightness<BV>)->Name("tightness/" name)->DenseRange(0, 3)->Iterations(1)
RAYACCEL_TIGHTNESS(AabbVolume, "aabb");
RAYACCEL_TIGHTNESS(SphereVolume, "sphere");
RAYACCEL_TIGHTNESS(ObbVolume, "obb");
RAYACCEL_TIGHTNESS(Kdop14Volume, "kdop14");
RAYACCEL_TIGHTNESS(Kdop18Volume, "kdop18");
RAYACCEL_TIGHTNESS(Kdop26Volume, "kdop26");
RAYACCEL_TIGHTNESS(HullVolume, "hull");
RAYACCEL_TIGHTNESS(CapsuleVolume, "capsule");

/// What each hull plane buys: tightness of the capped hull with 0..kMaxPlanes planes on shape 1 (a cap of a sphere
/// surface, a typical mesh node) and 2 (a thin rotated sliver); range(0) = planes, range(1) = shape.
void BM_HullPlanes(benchmark::State& state) {
  TightnessSums sums;
  const auto sets = shape_sets(int(state.range(1)));
  for (auto _ : state) {
    sums = {};
    for (const auto& pts : sets) sums.add(HullVolume::fit(pts, int(state.range(0))).surface_area(), pts);
  }
  state.counters["area_over_aabb"] = sums.over_aabb();
  state.counters["area_over_hull"] = sums.over_hull();
}
BENCHMARK(BM_HullPlanes)->Name("tightness/hull_planes")->ArgsProduct({{0, 2, 4, 6, 8}, {1, 2}})->Iterations(1);

}  // namespace
}  // namespace rayaccel
