// The cost of the double-precision path against float (issue #21): the same scene (a shared mesh, at its own
// coordinates and, for double, also moved to 1e7), the same primary rays (the standard camera, every other pixel of
// 1024 x 1024 in each direction), one thread, one ray at a time, closest hit, float bvh (binned SAH, AABB) and the
// default float bvh_wide against the double bvh built by the same builder over outward-rounded float boxes
// (double/double_bvh.h; kernels after Woop, Benthin, Wald 2013 and Ize 2013). Hits are checked against each other
// before timing.
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bvh_bench_scenes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/double/double_accelerator.h"

namespace rayaccel {
namespace {

struct DoubleBenchScene {
  std::vector<Ray> rays;        ///< every other pixel of the standard camera
  DoubleScene at_origin;        ///< the mesh in double, where it is
  std::vector<RayD> rays_d;     ///< the same rays in double (exact)
  DoubleScene far;              ///< the mesh moved by 1e7 on every axis
  std::vector<RayD> rays_far;   ///< the rays moved with it
};

const DoubleBenchScene* double_scene(const std::string& name) {
  static std::map<std::string, std::unique_ptr<DoubleBenchScene>> cache;
  if (auto it = cache.find(name); it != cache.end()) return it->second.get();
  const bvh_bench::BenchScene* s = bvh_bench::shared_scene(name);
  if (!s) return (cache[name] = nullptr).get();
  auto d = std::make_unique<DoubleBenchScene>();
  const DVec3 offset{1e7, 1e7, 1e7};
  d->at_origin = DoubleScene(to_double_mesh(s->scene.mesh()));
  d->far = DoubleScene(to_double_mesh(s->scene.mesh(), offset));
  for (int y = 0; y < 1024; y += 2) {
    for (int x = 0; x < 1024; x += 2) {
      const Ray& r = s->primary[static_cast<std::size_t>(y) * 1024 + static_cast<std::size_t>(x)];
      d->rays.push_back(r);
      const RayD rd{DVec3(r.origin), r.t_min, DVec3(r.direction), r.t_max};
      d->rays_d.push_back(rd);
      d->rays_far.push_back({rd.origin + offset, rd.t_min, rd.direction, rd.t_max});
    }
  }
  return (cache[name] = std::move(d)).get();
}

void set_rate(benchmark::State& state, std::size_t rays, std::size_t found) {
  const double n = static_cast<double>(rays);
  state.counters["Mrays/s"] =
      benchmark::Counter(n * 1e-6 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["hit%"] = 100.0 * static_cast<double>(found) / (n * static_cast<double>(state.iterations()));
}

void float_bvh(benchmark::State& state, const std::string& name, const std::string& spec) {
  const bvh_bench::BenchScene* s = bvh_bench::shared_scene(name);
  const DoubleBenchScene* d = double_scene(name);
  if (!s || !d) return state.SkipWithError(("scene " + name + " not found").c_str());
  auto accel = make_accelerator(spec);
  accel->build(s->scene);
  std::size_t found = 0;
  for (auto _ : state) {
    for (const Ray& r : d->rays) found += accel->intersect(r).found() ? 1 : 0;
  }
  set_rate(state, d->rays.size(), found);
}

void double_bvh(benchmark::State& state, const std::string& name, bool far) {
  const bvh_bench::BenchScene* s = bvh_bench::shared_scene(name);
  const DoubleBenchScene* d = double_scene(name);
  if (!s || !d) return state.SkipWithError(("scene " + name + " not found").c_str());
  auto accel = make_double_accelerator("bvh:builder=binned");
  accel->build(far ? d->far : d->at_origin);
  const std::vector<RayD>& rays = far ? d->rays_far : d->rays_d;
  // Check against the float path at the origin, where both see the same geometry and rays: same hit or miss, t
  // within float's rounding, on all but a few rays (at 1e7 the moved rays and mesh are rounded anew: 1% allowed).
  auto reference = make_accelerator("bvh:bv=aabb,builder=binned");
  reference->build(s->scene);
  std::size_t checked = 0, disagree = 0;
  for (std::size_t i = 0; i < rays.size(); i += 97, ++checked) {
    const Hit want = reference->intersect(d->rays[i]);
    const HitD got = accel->intersect(rays[i]);
    if (want.found() != got.found() || (want.found() && std::fabs(want.t - got.t) > 1e-4 * want.t)) ++disagree;
  }
  if (disagree * (far ? 100 : 1000) > checked) {
    return state.SkipWithError((std::to_string(disagree) + " of " + std::to_string(checked) +
                                " rays disagree with the float bvh").c_str());
  }
  std::size_t found = 0;
  for (auto _ : state) {
    for (const RayD& r : rays) found += accel->intersect(r).found() ? 1 : 0;
  }
  set_rate(state, rays.size(), found);
}

const bool registered = [] {
  for (const char* scene : {"bunny", "dragon"}) {
    const std::string s = scene;
    benchmark::RegisterBenchmark(("double_cost/" + s + "/float_bvh").c_str(), float_bvh, s,
                                 std::string("bvh:bv=aabb,builder=binned"))
        ->Unit(benchmark::kMillisecond);
    // The default float structure (eight-wide nodes, SIMD triangle blocks), which the double path has no twin of.
    benchmark::RegisterBenchmark(("double_cost/" + s + "/float_bvh_wide").c_str(), float_bvh, s,
                                 std::string("bvh_wide"))
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("double_cost/" + s + "/double_bvh").c_str(), double_bvh, s, false)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("double_cost/" + s + "/double_bvh_at_1e7").c_str(), double_bvh, s, true)
        ->Unit(benchmark::kMillisecond);
  }
  return true;
}();

}  // namespace
}  // namespace rayaccel
