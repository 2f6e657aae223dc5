// Benchmarks of the queries beyond the first hit on the shared meshes, one thread, one query at a time, in CPU time:
// closest points (rayaccel's branch and bound over bvh_wide and bvh against Embree's rtcPointQuery with a callback
// that runs the same point-triangle kernel) and all hits (rayaccel's count_hits against Embree's rtcIntersect1 with a
// context filter function that records each hit and rejects it so traversal goes on, Embree's documented way). The
// points: uniform in the mesh's box grown by a tenth, and near the surface (vertices moved by 1% of the diagonal);
// the rays: from outside the box through it, t_max = inf.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "bvh_bench_scenes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/geometry/point_triangle.h"

#ifdef RAYACCEL_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace rayaccel {
namespace {

constexpr std::size_t kQueries = 20000;

struct QueryInputs {
  std::vector<Vec3> box_points, surface_points;
  std::vector<Ray> rays;
};

const QueryInputs& inputs(const Scene& scene) {
  static std::map<const Scene*, QueryInputs> cache;
  auto [it, inserted] = cache.try_emplace(&scene);
  if (!inserted) return it->second;
  QueryInputs& q = it->second;
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const AABB& b = scene.bounds();
  const Vec3 lo = b.lo - b.extent() * 0.05f, size = b.extent() * 1.1f;
  const float diagonal = length(b.extent());
  for (std::size_t i = 0; i < kQueries; ++i) {
    q.box_points.push_back(lo + Vec3{unit(rng), unit(rng), unit(rng)} * size);
    const auto t = scene.triangle(static_cast<std::uint32_t>(rng() % scene.primitive_count()));
    q.surface_points.push_back(t[i % 3] + (Vec3{unit(rng), unit(rng), unit(rng)} - Vec3{0.5f}) * (0.02f * diagonal));
    const Vec3 target = b.lo + Vec3{unit(rng), unit(rng), unit(rng)} * b.extent();
    const Vec3 origin = b.center() + normalize(Vec3{unit(rng), unit(rng), unit(rng)} - Vec3{0.5f}) * diagonal;
    q.rays.push_back(Ray{origin, 0.0f, target - origin, std::numeric_limits<float>::infinity()});
  }
  return q;
}

void set_rate(benchmark::State& state, double per_iteration) {
  state.counters["queries/s"] =
      benchmark::Counter(per_iteration * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void closest_rayaccel(benchmark::State& state, const std::string& scene_name, const std::string& spec, bool near) {
  const bvh_bench::BenchScene* s = bvh_bench::shared_scene(scene_name);
  if (!s) return state.SkipWithError(("scene " + scene_name + " not found").c_str());
  auto accel = make_accelerator(spec);
  accel->build(s->scene);
  const auto& points = near ? inputs(s->scene).surface_points : inputs(s->scene).box_points;
  double sum = 0.0;
  for (auto _ : state) {
    for (const Vec3& p : points) sum += accel->closest_point(p).distance;
  }
  benchmark::DoNotOptimize(sum);
  state.counters["mean distance"] = sum / (static_cast<double>(points.size()) * static_cast<double>(state.iterations()));
  set_rate(state, static_cast<double>(points.size()));
}

void crossings_rayaccel(benchmark::State& state, const std::string& scene_name, const std::string& spec) {
  const bvh_bench::BenchScene* s = bvh_bench::shared_scene(scene_name);
  if (!s) return state.SkipWithError(("scene " + scene_name + " not found").c_str());
  auto accel = make_accelerator(spec);
  accel->build(s->scene);
  const auto& rays = inputs(s->scene).rays;
  std::size_t total = 0;
  std::vector<Hit> hits;
  for (auto _ : state) {
    for (const Ray& r : rays) total += accel->all_hits(r, hits);
  }
  state.counters["hits/ray"] = static_cast<double>(total) / (static_cast<double>(rays.size()) * state.iterations());
  set_rate(state, static_cast<double>(rays.size()));
}

#ifdef RAYACCEL_HAVE_EMBREE
/// Embree over the scene's valid triangles; `context_filter` builds the scene so that context filters run.
struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<float> vertices;
  std::vector<std::uint32_t> indices, prim_ids;
  const Scene* source = nullptr;

  EmbreeScene(const Scene& s, bool context_filter) : source(&s) {
    device = rtcNewDevice("threads=1");
    scene = rtcNewScene(device);
    if (context_filter) rtcSetSceneFlags(scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    for (std::uint32_t id = 0; id < s.primitive_count(); ++id) {
      if (!s.is_valid(id)) continue;
      for (const Vec3& v : s.triangle(id)) {
        indices.push_back(static_cast<std::uint32_t>(vertices.size() / 3));
        vertices.insert(vertices.end(), {v.x, v.y, v.z});
      }
      prim_ids.push_back(id);
    }
    vertices.push_back(0.0f);  // Embree may read 4 bytes past the last vertex
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices.data(), 0, 12,
                               (vertices.size() - 1) / 3);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices.data(), 0, 12,
                               indices.size() / 3);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
  }
  ~EmbreeScene() {
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
  }
  Vec3 vertex(std::uint32_t prim, int k) const {
    const float* v = &vertices[3 * indices[3 * prim + k]];
    return {v[0], v[1], v[2]};
  }
};

struct PointQueryState {
  const EmbreeScene* embree;
  Vec3 point;
  double best_squared;
  std::uint32_t prim;
};

/// Embree's point-query callback: the same point-triangle kernel as rayaccel's; shrinks the query radius on success.
bool closest_callback(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<PointQueryState*>(args->userPtr);
  const TrianglePoint t = closest_point_on_triangle(q->point, q->embree->vertex(args->primID, 0),
                                                    q->embree->vertex(args->primID, 1),
                                                    q->embree->vertex(args->primID, 2));
  if (t.distance_squared >= q->best_squared) return false;
  q->best_squared = t.distance_squared;
  q->prim = args->primID;
  args->query->radius = static_cast<float>(std::sqrt(t.distance_squared));
  return true;
}

void closest_embree(benchmark::State& state, const std::string& scene_name, bool near) {
  const bvh_bench::BenchScene* s = bvh_bench::shared_scene(scene_name);
  if (!s) return state.SkipWithError(("scene " + scene_name + " not found").c_str());
  const EmbreeScene embree(s->scene, false);
  const auto& points = near ? inputs(s->scene).surface_points : inputs(s->scene).box_points;
  double sum = 0.0;
  for (auto _ : state) {
    for (const Vec3& p : points) {
      RTCPointQuery query{p.x, p.y, p.z, 0.0f, std::numeric_limits<float>::infinity()};
      RTCPointQueryContext context;
      rtcInitPointQueryContext(&context);
      PointQueryState q{&embree, p, std::numeric_limits<double>::infinity(), RTC_INVALID_GEOMETRY_ID};
      rtcPointQuery(embree.scene, &query, &context, closest_callback, &q);
      sum += std::sqrt(q.best_squared);
    }
  }
  benchmark::DoNotOptimize(sum);
  state.counters["mean distance"] = sum / (static_cast<double>(points.size()) * static_cast<double>(state.iterations()));
  set_rate(state, static_cast<double>(points.size()));
}

/// An intersect context carrying the hits its filter records.
struct CollectContext {
  RTCIntersectContext context;
  std::vector<std::pair<float, std::uint32_t>>* hits;
};

void collect_filter(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<const CollectContext*>(args->context);
  const RTCRay ray = rtcGetRayFromRayN(args->ray, args->N, 0);
  const RTCHit hit = rtcGetHitFromHitN(args->hit, args->N, 0);
  c->hits->push_back({ray.tfar, hit.primID});
  args->valid[0] = 0;  // rejected: traversal continues to the next hit
}

void crossings_embree(benchmark::State& state, const std::string& scene_name) {
  const bvh_bench::BenchScene* s = bvh_bench::shared_scene(scene_name);
  if (!s) return state.SkipWithError(("scene " + scene_name + " not found").c_str());
  const EmbreeScene embree(s->scene, true);
  const auto& rays = inputs(s->scene).rays;
  std::vector<std::pair<float, std::uint32_t>> hits;
  std::size_t total = 0;
  for (auto _ : state) {
    for (const Ray& r : rays) {
      hits.clear();
      CollectContext c;
      rtcInitIntersectContext(&c.context);
      c.context.filter = collect_filter;
      c.hits = &hits;
      RTCRayHit rh{};
      rh.ray = {r.origin.x, r.origin.y, r.origin.z, r.t_min, r.direction.x, r.direction.y, r.direction.z, 0.0f,
                r.t_max, 0xFFFFFFFFu, 0, 0};
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(embree.scene, &c.context, &rh);
      std::sort(hits.begin(), hits.end());  // by t, as rayaccel returns them
      total += hits.size();
    }
  }
  state.counters["hits/ray"] = static_cast<double>(total) / (static_cast<double>(rays.size()) * state.iterations());
  set_rate(state, static_cast<double>(rays.size()));
}
#endif

void register_all() {
  for (const char* scene : {"bunny", "dragon"}) {
    for (bool near : {false, true}) {
      const std::string where = near ? "near" : "box";
      for (const char* spec : {"bvh_wide", "bvh"}) {
        benchmark::RegisterBenchmark(("closest/" + std::string(scene) + "/" + where + "/" + spec).c_str(),
                                     closest_rayaccel, scene, spec, near)
            ->Unit(benchmark::kMillisecond);
      }
#ifdef RAYACCEL_HAVE_EMBREE
      benchmark::RegisterBenchmark(("closest/" + std::string(scene) + "/" + where + "/embree").c_str(),
                                   closest_embree, scene, near)
          ->Unit(benchmark::kMillisecond);
#endif
    }
    for (const char* spec : {"bvh_wide", "bvh"}) {
      benchmark::RegisterBenchmark(("all_hits/" + std::string(scene) + "/" + spec).c_str(), crossings_rayaccel, scene,
                                   spec)
          ->Unit(benchmark::kMillisecond);
    }
#ifdef RAYACCEL_HAVE_EMBREE
    benchmark::RegisterBenchmark(("all_hits/" + std::string(scene) + "/embree").c_str(), crossings_embree, scene)
        ->Unit(benchmark::kMillisecond);
#endif
  }
}

const bool registered = (register_all(), true);

}  // namespace
}  // namespace rayaccel
