// bvh_wide refit against rebuild on the shared dragon and bunny, twisted about their vertical axis a little more each
// frame: the time of update() (a refit) and of build(), and the primary-ray speed after each, since a refitted tree
// keeps its shape while the mesh moves away from it, with the nodes entered and triangles tested per ray, which the
// machine's load does not change (figures in BENCHMARKS.md, "Refit against rebuild").
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bvh_bench_scenes.h"
#include "rayaccel/accel/registry.h"

namespace rayaccel {
namespace {

/// A private copy of a shared scene that can move: frame f twists it by 0.5 f radians from bottom to top.
struct TwistedScene {
  std::vector<Vec3> rest;
  AABB box;
  Scene scene;
  const std::vector<Ray>* rays = nullptr;

  static TwistedScene* get(const std::string& name) {
    static std::map<std::string, std::unique_ptr<TwistedScene>> cache;
    auto& slot = cache[name];
    if (!slot) {
      const bvh_bench::BenchScene* base = bvh_bench::shared_scene(name);
      if (!base) return nullptr;
      slot = std::make_unique<TwistedScene>();
      slot->rest = base->scene.mesh().vertices;
      slot->box = base->scene.bounds();
      slot->scene = Scene::from_mesh(base->scene.mesh(), name);
      slot->rays = &base->primary;
    }
    return slot.get();
  }

  void frame(int f) {
    std::vector<Vec3> v = rest;
    const Vec3 c = box.center();
    const float height = box.hi.y - box.lo.y;
    for (Vec3& p : v) {
      const float a = 0.5f * static_cast<float>(f) * (p.y - box.lo.y) / height;
      const float x = p.x - c.x, z = p.z - c.z;
      p = Vec3{c.x + std::cos(a) * x - std::sin(a) * z, p.y, c.z + std::sin(a) * x + std::cos(a) * z};
    }
    scene.set_vertices(v);
  }
};

/// Time of one update() (refitting) or build() per iteration, the scene moved to frame 1 beforehand.
void wide_update(benchmark::State& state, const std::string& name, bool refit) {
  TwistedScene* s = TwistedScene::get(name);
  if (!s) return state.SkipWithError("shared scene missing");
  s->frame(0);
  auto accel = make_accelerator("bvh_wide");
  accel->build(s->scene);
  s->frame(1);
  for (auto _ : state) {
    if (refit) {
      if (accel->update(s->scene) != UpdateKind::refitted) return state.SkipWithError("did not refit");
    } else {
      accel->build(s->scene);
    }
  }
  state.counters["triangles"] = s->scene.primitive_count();
}

/// Primary-ray speed at frame `frame`: after refitting the frame-0 tree every frame up to it, or after a rebuild.
void wide_trace(benchmark::State& state, const std::string& name, int frame, bool refit) {
  TwistedScene* s = TwistedScene::get(name);
  if (!s) return state.SkipWithError("shared scene missing");
  s->frame(0);
  auto accel = make_accelerator("bvh_wide");
  accel->build(s->scene);
  for (int f = 1; f <= frame; ++f) {
    s->frame(f);
    if (refit) accel->update(s->scene);
  }
  if (!refit) accel->build(s->scene);
  auto brute = make_accelerator("bvh:builder=binned");  // the reference for a sample of the rays
  brute->build(s->scene);
  for (std::size_t i = 0; i < s->rays->size(); i += 997) {
    const Hit a = accel->intersect((*s->rays)[i]), b = brute->intersect((*s->rays)[i]);
    if (a.prim_id != b.prim_id && a.t != b.t) return state.SkipWithError("hit differs from the reference");
  }
  // Work per ray, which the machine's load does not change: nodes entered and triangles tested, over every 16th ray.
  TraversalStats work;
  std::size_t sampled = 0;
  for (std::size_t i = 0; i < s->rays->size(); i += 16, ++sampled) accel->intersect((*s->rays)[i], work);
  state.counters["nodes/ray"] = static_cast<double>(work.nodes_visited) / static_cast<double>(sampled);
  state.counters["tests/ray"] = static_cast<double>(work.primitives_tested) / static_cast<double>(sampled);
  std::vector<Hit> hits(s->rays->size());
  for (auto _ : state) {
    accel->intersect(*s->rays, hits);
    benchmark::DoNotOptimize(hits.data());
  }
  state.counters["Mrays/s"] = benchmark::Counter(static_cast<double>(s->rays->size()) * 1e-6 *
                                                     static_cast<double>(state.iterations()),
                                                 benchmark::Counter::kIsRate);
}

void register_all() {
  for (const char* name : {"bunny", "dragon"}) {
    for (const bool refit : {true, false}) {
      benchmark::RegisterBenchmark((std::string("wide_") + (refit ? "refit/" : "rebuild/") + name).c_str(),
                                   [=](benchmark::State& st) { wide_update(st, name, refit); })
          ->Iterations(5)  // fixed counts: each call's setup (a build of the dragon) is not repeated to calibrate
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
    for (const int frame : {1, 2, 4}) {
      for (const bool refit : {true, false}) {
        benchmark::RegisterBenchmark((std::string("wide_trace_after_") + (refit ? "refit/" : "rebuild/") + name +
                                      "/frame" + std::to_string(frame))
                                         .c_str(),
                                     [=](benchmark::State& st) { wide_trace(st, name, frame, refit); })
            ->Iterations(3)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
    }
  }
}

const int registered = (register_all(), 0);

}  // namespace
}  // namespace rayaccel
