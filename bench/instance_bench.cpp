// Instanced against flattened scenes: N copies of the shared bunny on a grid (each turned about Y and scaled), as
// one InstancedAccelerator (bottom level bvh_wide, built once) and, for small N, as one flattened triangle scene
// under bvh_wide. Build time, bytes held (structure plus scene arrays), camera-ray throughput (512 x 512 rays of
// Camera::framing over the whole grid), and the top-level rebuild and refit after every instance moved; with
// Embree, the same scene as Embree instances (one triangle scene, N RTC_GEOMETRY_TYPE_INSTANCE geometries, default
// flags).
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "bvh_bench_scenes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/instance/flatten.h"
#include "rayaccel/instance/instanced_accelerator.h"

#ifdef RAYACCEL_HAVE_EMBREE
#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <atomic>
#endif

namespace rayaccel {
namespace {

std::shared_ptr<const Scene> bunny() {
  static const std::shared_ptr<const Scene> scene = [] {
    try {
      return std::make_shared<const Scene>(
          Scene::from_mesh(import_mesh(bvh_bench::scenes_dir() / "bunny.ply"), "bunny"));
    } catch (const Error&) {
      return std::shared_ptr<const Scene>();
    }
  }();
  return scene;
}

Affine3 placement(std::uint32_t i, std::uint32_t side, const AABB& box, std::mt19937& rng, double turn) {
  const Vec3 e = box.extent();
  const double spacing = 1.2 * std::max({e.x, e.y, e.z});
  std::uniform_real_distribution<double> angle(0.0, 6.283185307179586), scale(0.7, 1.0);
  const Vec3 c = box.center();
  return Affine3::translation(spacing * (i % side), spacing * (i / side), 0.0) *
         Affine3::rotation({0.0f, 1.0f, 0.0f}, angle(rng) + turn) * Affine3::scaling(scale(rng), scale(rng), scale(rng)) *
         Affine3::translation(-c.x, -c.y, -c.z);
}

InstancedScene bunny_grid(std::uint32_t count, double turn = 0.0) {
  InstancedScene scene;
  scene.add_geometry(bunny());
  const auto side = static_cast<std::uint32_t>(std::ceil(std::sqrt(double(count))));
  std::mt19937 rng(1);
  for (std::uint32_t i = 0; i < count; ++i) scene.add_instance(0, placement(i, side, bunny()->bounds(), rng, turn));
  return scene;
}

std::vector<Ray> camera_rays(const AABB& box) {
  constexpr int kSize = 512;
  const CameraFrame frame = Camera::framing(box).frame(kSize, kSize);
  std::vector<Ray> rays;
  rays.reserve(kSize * kSize);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) rays.push_back(frame.ray(x, y));
  }
  return rays;
}

AABB world_bounds(const InstancedScene& scene) {
  AABB box;
  for (const Instance& instance : scene.instances()) {
    box.extend(transform_box(instance.transform, scene.geometry(instance.geometry).bounds()));
  }
  return box;
}

void instanced_build(benchmark::State& state) {
  if (!bunny()) return state.SkipWithError("shared/scenes/bunny.ply not found");
  const InstancedScene scene = bunny_grid(static_cast<std::uint32_t>(state.range(0)));
  InstancedAccelerator accel;
  for (auto _ : state) accel.build(scene);
  state.counters["MB"] = double(accel.memory_bytes() + scene.memory_bytes()) / 1e6;
  state.counters["top_MB"] = double(accel.top_memory_bytes()) / 1e6;
  state.counters["flat_Mtris"] = double(scene.flattened_primitive_count()) / 1e6;
}

void instanced_trace(benchmark::State& state) {
  if (!bunny()) return state.SkipWithError("shared/scenes/bunny.ply not found");
  const InstancedScene scene = bunny_grid(static_cast<std::uint32_t>(state.range(0)));
  InstancedAccelerator accel;
  accel.build(scene);
  const std::vector<Ray> rays = camera_rays(world_bounds(scene));
  std::vector<InstanceHit> hits(rays.size());
  for (auto _ : state) accel.intersect(rays, hits);
  std::size_t found = 0;
  for (const InstanceHit& hit : hits) found += hit.found() ? 1 : 0;
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(rays.size()));
  state.counters["hit_fraction"] = double(found) / double(rays.size());
}

/// The same camera rays on one thread (one intersect() per ray), with top level `top` (InstancedAcceleratorOptions):
/// "bvh_top" (TopLevelBvh) against registry structures over one user primitive per instance.
void instanced_trace_top(benchmark::State& state, const char* top) {
  if (!bunny()) return state.SkipWithError("shared/scenes/bunny.ply not found");
  const InstancedScene scene = bunny_grid(static_cast<std::uint32_t>(state.range(0)));
  InstancedAcceleratorOptions options;
  options.top = top;
  InstancedAccelerator accel(options);
  accel.build(scene);
  const std::vector<Ray> rays = camera_rays(world_bounds(scene));
  std::size_t found = 0;
  for (auto _ : state) {
    found = 0;
    for (const Ray& ray : rays) found += accel.intersect(ray).found() ? 1 : 0;
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(rays.size()));
  state.counters["hit_fraction"] = double(found) / double(rays.size());
  state.counters["top_KB"] = double(accel.top_memory_bytes()) / 1e3;
}

/// Every instance moved between two poses, then the top level brought up to date by `update` (timed).
template <class Update>
void move_every_instance(benchmark::State& state, Update update) {
  if (!bunny()) return state.SkipWithError("shared/scenes/bunny.ply not found");
  const auto count = static_cast<std::uint32_t>(state.range(0));
  InstancedScene scene = bunny_grid(count);
  InstancedAccelerator accel;
  accel.build(scene);
  const InstancedScene moved = bunny_grid(count, 0.5);  // the same grid, every bunny turned by half a radian
  const InstancedScene rest = bunny_grid(count);
  int frame = 0;
  for (auto _ : state) {
    state.PauseTiming();
    const InstancedScene& next = (++frame % 2) ? moved : rest;
    for (std::uint32_t i = 0; i < count; ++i) scene.set_transform(i, next.instance(i).transform);
    state.ResumeTiming();
    update(accel);
  }
}

void instanced_rebuild_top(benchmark::State& state) {
  move_every_instance(state, [](InstancedAccelerator& accel) { accel.rebuild_top(); });
}

/// The same moves, the top level refitted (tree kept, boxes recomputed bottom-up).
void instanced_refit_top(benchmark::State& state) {
  move_every_instance(state, [](InstancedAccelerator& accel) { benchmark::DoNotOptimize(accel.update_top()); });
}

void flattened_build(benchmark::State& state) {
  if (!bunny()) return state.SkipWithError("shared/scenes/bunny.ply not found");
  const FlattenedScene flat = flatten(bunny_grid(static_cast<std::uint32_t>(state.range(0))));
  const auto accel = make_accelerator("bvh_wide");
  for (auto _ : state) accel->build(flat.scene);
  state.counters["MB"] = double(accel->memory_bytes() + flat.scene.memory_bytes()) / 1e6;
}

void flattened_trace(benchmark::State& state) {
  if (!bunny()) return state.SkipWithError("shared/scenes/bunny.ply not found");
  const InstancedScene scene = bunny_grid(static_cast<std::uint32_t>(state.range(0)));
  const FlattenedScene flat = flatten(scene);
  const auto accel = make_accelerator("bvh_wide");
  accel->build(flat.scene);
  const std::vector<Ray> rays = camera_rays(world_bounds(scene));
  std::vector<Hit> hits(rays.size());
  for (auto _ : state) accel->intersect(rays, hits);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(rays.size()));
}

BENCHMARK(instanced_build)->Arg(50)->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(instanced_trace)->Arg(50)->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(instanced_trace_top, bvh_top, "bvh_top")->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(instanced_trace_top, bvh_wide, "bvh_wide")->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(instanced_trace_top, bvh, "bvh")->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(instanced_rebuild_top)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(instanced_refit_top)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(flattened_build)->Arg(50)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(flattened_trace)->Arg(50)->Unit(benchmark::kMillisecond)->UseRealTime();

#ifdef RAYACCEL_HAVE_EMBREE
/// The bunny grid as Embree instances: one committed triangle scene, one instance geometry per placement.
class EmbreeInstances {
 public:
  explicit EmbreeInstances(const InstancedScene& scene) : device_(rtcNewDevice(nullptr)) {
    rtcSetDeviceMemoryMonitorFunction(
        device_,
        [](void* user, ssize_t bytes, bool) {
          static_cast<std::atomic<std::int64_t>*>(user)->fetch_add(bytes);
          return true;
        },
        &allocated_);
    const Scene& mesh = scene.geometry(0);
    mesh_ = rtcNewScene(device_);
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), mesh.mesh().vertices.size()));
    for (std::size_t i = 0; i < mesh.mesh().vertices.size(); ++i) {
      const Vec3& v = mesh.mesh().vertices[i];
      vertices[3 * i] = v.x;
      vertices[3 * i + 1] = v.y;
      vertices[3 * i + 2] = v.z;
    }
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), mesh.mesh().triangles.size()));
    for (std::size_t i = 0; i < mesh.mesh().triangles.size(); ++i) {
      for (std::size_t k = 0; k < 3; ++k) indices[3 * i + k] = mesh.mesh().triangles[i][k];
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(mesh_, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(mesh_);
    top_ = rtcNewScene(device_);
    for (const Instance& instance : scene.instances()) {
      RTCGeometry i = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(i, mesh_);
      rtcSetGeometryTimeStepCount(i, 1);
      set(i, instance.transform);
      rtcAttachGeometry(top_, i);
      rtcReleaseGeometry(i);
    }
    rtcCommitScene(top_);
  }
  ~EmbreeInstances() {
    rtcReleaseScene(top_);
    rtcReleaseScene(mesh_);
    rtcReleaseDevice(device_);
  }
  EmbreeInstances(const EmbreeInstances&) = delete;
  EmbreeInstances& operator=(const EmbreeInstances&) = delete;

  /// New transforms for every instance, then the top scene's commit (Embree rebuilds its top level).
  void move(const InstancedScene& scene) {
    for (std::uint32_t i = 0; i < scene.instance_count(); ++i) set(rtcGetGeometry(top_, i), scene.instance(i).transform);
  }
  void commit() { rtcCommitScene(top_); }

  /// Closest hits of a batch; returns how many rays hit.
  std::size_t intersect(const std::vector<Ray>& rays) const {
    std::atomic<std::size_t> found{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 1024), [&](const auto& range) {
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      std::size_t local = 0;
      for (std::size_t r = range.begin(); r < range.end(); ++r) {
        RTCRayHit rh{};
        const Ray& ray = rays[r];
        rh.ray.org_x = ray.origin.x, rh.ray.org_y = ray.origin.y, rh.ray.org_z = ray.origin.z;
        rh.ray.dir_x = ray.direction.x, rh.ray.dir_y = ray.direction.y, rh.ray.dir_z = ray.direction.z;
        rh.ray.tnear = ray.t_min;
        rh.ray.tfar = ray.t_max;
        rh.ray.mask = ~0u;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(top_, &context, &rh);
        local += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? 1 : 0;
      }
      found += local;
    });
    return found;
  }
  double megabytes() const { return double(allocated_.load()) / 1e6; }

 private:
  static void set(RTCGeometry geometry, const Affine3& transform) {
    float rows[12];
    for (std::size_t k = 0; k < 12; ++k) rows[k] = static_cast<float>(transform.m[k]);
    rtcSetGeometryTransform(geometry, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, rows);
    rtcCommitGeometry(geometry);
  }

  std::atomic<std::int64_t> allocated_{0};
  RTCDevice device_;
  RTCScene mesh_ = nullptr;
  RTCScene top_ = nullptr;
};

void embree_instanced_build(benchmark::State& state) {
  if (!bunny()) return state.SkipWithError("shared/scenes/bunny.ply not found");
  const InstancedScene scene = bunny_grid(static_cast<std::uint32_t>(state.range(0)));
  double megabytes = 0.0;
  for (auto _ : state) {
    EmbreeInstances embree(scene);
    megabytes = embree.megabytes();
  }
  state.counters["MB"] = megabytes;
}

void embree_instanced_trace(benchmark::State& state) {
  if (!bunny()) return state.SkipWithError("shared/scenes/bunny.ply not found");
  const InstancedScene scene = bunny_grid(static_cast<std::uint32_t>(state.range(0)));
  const EmbreeInstances embree(scene);
  const std::vector<Ray> rays = camera_rays(world_bounds(scene));
  std::size_t found = 0;
  for (auto _ : state) found = embree.intersect(rays);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(rays.size()));
  state.counters["hit_fraction"] = double(found) / double(rays.size());
}

void embree_instanced_rebuild_top(benchmark::State& state) {
  if (!bunny()) return state.SkipWithError("shared/scenes/bunny.ply not found");
  const auto count = static_cast<std::uint32_t>(state.range(0));
  const InstancedScene moved = bunny_grid(count, 0.5);
  const InstancedScene rest = bunny_grid(count);
  EmbreeInstances embree(rest);
  int frame = 0;
  for (auto _ : state) {
    state.PauseTiming();
    embree.move((++frame % 2) ? moved : rest);
    state.ResumeTiming();
    embree.commit();
  }
}

BENCHMARK(embree_instanced_build)->Arg(50)->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(embree_instanced_trace)->Arg(50)->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(embree_instanced_rebuild_top)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond)->UseRealTime();
#endif

}  // namespace
}  // namespace rayaccel
