// BVH build time and primary-ray throughput (Mrays/s, 1024x1024 standard camera) per builder on the shared scenes:
// batched over all threads (wall time), and one thread in CPU time. Before the batched timing, a sample of the rays
// is checked against brute force.
#include <benchmark/benchmark.h>

#include <cmath>

#include "bvh_bench_scenes.h"
#include "rayaccel/accel/brute_force.h"
#include "rayaccel/accel/registry.h"

namespace rayaccel {
namespace {

double statistic(const Accelerator& a, const std::string& name) {
  for (const auto& s : a.build_statistics()) {
    if (s.name == name) return s.value;
  }
  return 0.0;
}

void set_tree_counters(benchmark::State& state, const Accelerator& a) {
  state.counters["sah"] = statistic(a, "sah_cost");
  state.counters["nodes"] = statistic(a, "node_count");
  state.counters["depth"] = statistic(a, "depth");
  state.counters["refs/prim"] = statistic(a, "references_per_primitive");
}

void bvh_build(benchmark::State& state, const std::string& scene_name, const std::string& spec) {
  const bvh_bench::BenchScene* s = bvh_bench::shared_scene(scene_name);
  if (!s) return state.SkipWithError(("scene " + scene_name + " not found").c_str());
  auto accel = make_accelerator(spec);
  for (auto _ : state) accel->build(s->scene);
  set_tree_counters(state, *accel);
  state.counters["tris"] = s->scene.primitive_count();
}

void bvh_primary(benchmark::State& state, const std::string& scene_name, const std::string& spec) {
  const bvh_bench::BenchScene* s = bvh_bench::shared_scene(scene_name);
  if (!s) return state.SkipWithError(("scene " + scene_name + " not found").c_str());
  auto accel = make_accelerator(spec);
  accel->build(s->scene);
  BruteForce oracle;
  oracle.build(s->scene);
  for (std::size_t i = 0; i < s->primary.size(); i += s->primary.size() / 256) {
    const Hit want = oracle.intersect(s->primary[i]), got = accel->intersect(s->primary[i]);
    if (want.found() != got.found() || (want.found() && std::fabs(want.t - got.t) > 1e-6f * want.t)) {
      return state.SkipWithError(("ray " + std::to_string(i) + " disagrees with brute force").c_str());
    }
  }
  std::vector<Hit> hits(s->primary.size());
  for (auto _ : state) {
    accel->intersect(s->primary, hits);
    benchmark::DoNotOptimize(hits.data());
  }
  std::vector<TraversalStats> per_ray(s->primary.size());
  accel->intersect(s->primary, hits, per_ray);
  TraversalStats total;
  for (const auto& t : per_ray) total += t;
  const double n = static_cast<double>(s->primary.size());
  state.counters["Mrays/s"] =
      benchmark::Counter(n * 1e-6 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["nodes/ray"] = static_cast<double>(total.nodes_visited) / n;
  state.counters["tests/ray"] = static_cast<double>(total.primitives_tested) / n;
  set_tree_counters(state, *accel);
}

/// One thread, one ray at a time, timed in CPU time: a per-core figure that holds up on a loaded machine.
void bvh_primary_one_thread(benchmark::State& state, const std::string& scene_name, const std::string& spec) {
  const bvh_bench::BenchScene* s = bvh_bench::shared_scene(scene_name);
  if (!s) return state.SkipWithError(("scene " + scene_name + " not found").c_str());
  auto accel = make_accelerator(spec);
  accel->build(s->scene);
  std::size_t found = 0;
  for (auto _ : state) {
    for (const Ray& r : s->primary) found += accel->intersect(r).found() ? 1 : 0;
  }
  benchmark::DoNotOptimize(found);
  const double n = static_cast<double>(s->primary.size());
  state.counters["Mrays/s"] =
      benchmark::Counter(n * 1e-6 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["hit%"] = 100.0 * static_cast<double>(found) / (n * static_cast<double>(state.iterations()));
}

void register_all() {
  for (const char* scene : {"bunny", "crytek_sponza", "dragon"}) {
    for (const char* builder : {"binned", "sweep", "sbvh", "lbvh", "ploc"}) {
      const std::string spec = std::string("bvh:bv=aabb,builder=") + builder;
      benchmark::RegisterBenchmark(("bvh_build/" + std::string(scene) + "/" + builder).c_str(), bvh_build, scene, spec)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->Iterations(3);
      benchmark::RegisterBenchmark(("bvh_primary/" + std::string(scene) + "/" + builder).c_str(), bvh_primary, scene,
                                   spec)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->MinTime(1.0);
      benchmark::RegisterBenchmark(("bvh_primary_1t/" + std::string(scene) + "/" + builder).c_str(),
                                   bvh_primary_one_thread, scene, spec)
          ->Unit(benchmark::kMillisecond)
          ->MinTime(1.0);
    }
  }
}

const bool registered = (register_all(), true);

}  // namespace
}  // namespace rayaccel
