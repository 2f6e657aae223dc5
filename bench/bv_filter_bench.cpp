// The AABB-first filter for the tight volumes (OBB, k-DOP 26, capped hull): each node also stores its contents' box,
// tested first; only rays that touch the box pay for the tight test. Measured as one-thread primary-ray throughput
// of Bvh<AabbFirst<BV>> against Bvh<BV> on the shared scenes (the capped hull has the filter built in).
#include <benchmark/benchmark.h>

#include <span>

#include "bvh_bench_scenes.h"
#include "rayaccel/bv/aabb_volume.h"
#include "rayaccel/bv/hull_volume.h"
#include "rayaccel/bv/kdop_volume.h"
#include "rayaccel/bv/obb_volume.h"
#include "rayaccel/bvh/bvh.h"

namespace rayaccel {
namespace {

template <class BV>
constexpr const char* filtered_name() {
  if constexpr (std::is_same_v<BV, ObbVolume>) return "aabb+obb";
  else return "aabb+kdop26";
}

/// BV behind its contents' box: the box's robust slab test first, the tight test only on the box's interval.
template <BoundingVolume BV>
struct AabbFirst {
  static constexpr const char* kName = filtered_name<BV>();
  struct RayContext {
    const PreparedRay* ray;
    typename BV::RayContext inner;
  };
  AABB box;  ///< 24 bytes on top of BV
  BV inner;

  static RayContext prepare(const PreparedRay& ray) { return {&ray, BV::prepare(ray)}; }
  static AabbFirst fit(std::span<const Vec3> points) {
    AabbFirst v;
    for (const Vec3& p : points) v.box.extend(p);
    v.inner = BV::fit(points);
    return v;
  }
  bool intersect(const RayContext& c, float t_min, float t_max, float* t_entry) const {
    float t_near = t_min, t_far = t_max;
    if (!clip_ray_to_box(*c.ray, box, t_near, t_far)) {
      *t_entry = t_near;
      return false;
    }
    return inner.intersect(c.inner, t_near, t_far, t_entry);
  }
  float surface_area() const { return inner.surface_area(); }
  AABB bounds() const { return box; }
  bool contains(const Vec3& p) const { return inner.contains(p); }
};

template <BoundingVolume BV>
void primary_one_thread(benchmark::State& state, const std::string& scene_name) {
  const bvh_bench::BenchScene* s = bvh_bench::shared_scene(scene_name);
  if (!s) return state.SkipWithError(("scene " + scene_name + " not found").c_str());
  Bvh<BV> bvh;
  bvh.build(s->scene);
  std::size_t found = 0;
  TraversalStats stats;
  for (auto _ : state) {
    for (const Ray& r : s->primary) found += bvh.intersect(r).found() ? 1 : 0;
  }
  for (const Ray& r : s->primary) bvh.intersect(r, stats);
  benchmark::DoNotOptimize(found);
  const double n = static_cast<double>(s->primary.size());
  state.counters["Mrays/s"] =
      benchmark::Counter(n * 1e-6 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["nodes/ray"] = double(stats.nodes_visited) / n;
  state.counters["B/node"] = sizeof(typename Bvh<BV>::Node);
}

void register_all() {
  for (const char* scene : {"bunny", "crytek_sponza", "conference"}) {
    const std::string prefix = std::string("aabb_first/") + scene + "/";
    const auto add = [&](const std::string& name, auto function) {
      benchmark::RegisterBenchmark((prefix + name).c_str(), function, std::string(scene))
          ->Unit(benchmark::kMillisecond)
          ->Iterations(2);
    };
    add("aabb", primary_one_thread<AabbVolume>);
    add("obb", primary_one_thread<ObbVolume>);
    add("aabb+obb", primary_one_thread<AabbFirst<ObbVolume>>);
    add("kdop26", primary_one_thread<Kdop26Volume>);
    add("aabb+kdop26", primary_one_thread<AabbFirst<Kdop26Volume>>);
    add("hull", primary_one_thread<HullVolume>);
  }
}

const bool registered = (register_all(), true);

}  // namespace
}  // namespace rayaccel
