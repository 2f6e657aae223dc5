// Instanced against flattened scenes: N copies of the shared bunny on a grid (each turned about Y and scaled), as
// one InstancedAccelerator (bottom level bvh_wide, built once) and, for small N, as one flattened triangle scene
// under bvh_wide. Build time, bytes held (structure plus scene arrays), camera-ray throughput (512 x 512 rays of
// Camera::framing over the whole grid), and the top-level rebuild after every instance moved.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "bvh_bench_scenes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/instance/flatten.h"
#include "rayaccel/instance/instanced_accelerator.h"

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

void instanced_rebuild_top(benchmark::State& state) {
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
    accel.rebuild_top();
  }
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
BENCHMARK(instanced_rebuild_top)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(flattened_build)->Arg(50)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(flattened_trace)->Arg(50)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace rayaccel
