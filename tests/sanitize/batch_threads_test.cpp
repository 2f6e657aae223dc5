// The ThreadSanitizer run (scripts/ci_tsan.sh): the batch and packet queries (closest and any hit) of every structure
// kind on one shared structure from 4 threads at once, checked against brute force. Built as its own small executable
// (rayaccel_tsan_test) under RAYACCEL_SANITIZE_THREAD, not as part of rayaccel_tests.
// TBB runs with one thread, so each caller's batch runs in the caller: Debian's libtbb is not instrumented, TSan
// cannot see its task joins, and with TBB workers every write after a parallel_for to memory a worker had read
// (the body's std::function, the caller's stack) is reported as a race. The threads here are std::threads, whose
// start and join TSan sees, so what is checked is what matters to users: concurrent queries on one structure
// (shared nodes, per-thread mailboxes and stacks) never race.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "rayaccel/accel/registry.h"
#include "rayaccel/scene/import.h"

namespace rayaccel {
namespace {

std::vector<Ray> random_rays(const AABB& box, std::size_t count) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Ray> rays(count);
  for (Ray& r : rays) {
    const Vec3 e = box.extent();
    const Vec3 target = box.lo + Vec3{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z};
    r.origin = box.center() + Vec3{u(rng) - 0.5f, u(rng) - 0.5f, 2.0f} * length(e);
    r.direction = target - r.origin;
  }
  return rays;
}

TEST(ThreadSanitizer, BatchAndPacketQueriesFromSeveralThreads) {
  tbb::global_control one_tbb_thread(tbb::global_control::max_allowed_parallelism, 1);
  const Scene scene = load_scene("builtin:default");
  const std::vector<Ray> rays = random_rays(scene.bounds(), 20000);
  auto oracle = make_accelerator("brute_force");
  oracle->build(scene);
  std::vector<Hit> expected(rays.size());
  oracle->intersect(rays, expected);
  for (const char* spec : {"bvh", "bvh_wide", "grid", "grid2", "kdtree", "octree", "bvh:builder=ploc",
                           "bvh:builder=lbvh", "bvh:builder=sbvh"}) {
    auto accel = make_accelerator(spec);
    accel->build(scene);
    std::vector<std::thread> callers;
    std::vector<std::size_t> faults(4, 0);
    for (int t = 0; t < 4; ++t) {
      callers.emplace_back([&, t] {
        std::vector<Hit> hits(rays.size());
        std::vector<std::uint8_t> occluded(rays.size());
        if (t % 2 == 0) {
          accel->intersect(rays, hits);
        } else {
          accel->intersect_packets(rays, hits);
        }
        if (t < 2) {
          accel->occluded(rays, occluded);
        } else {
          accel->occluded_packets(rays, occluded);  // the any-hit packets (one by one where a structure has none)
        }
        for (std::size_t i = 0; i < rays.size(); ++i) {
          // The conformance suite's t tolerance (oracle.h): the same kernel, possibly another rounding order.
          const bool same_t = !expected[i].found() || std::fabs(hits[i].t - expected[i].t) <= 1e-6f * expected[i].t;
          faults[t] += hits[i].found() != expected[i].found() || !same_t ? 1 : 0;
          faults[t] += (occluded[i] != 0) != expected[i].found() ? 1 : 0;
        }
      });
    }
    for (auto& c : callers) c.join();
    for (int t = 0; t < 4; ++t) EXPECT_EQ(faults[t], 0u) << spec << ", thread " << t;
  }
}

}  // namespace
}  // namespace rayaccel
