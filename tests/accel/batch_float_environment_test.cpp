// Batches (intersect/occluded/intersect_packets over spans, run as TBB tasks) answer exactly as single-ray calls on the calling thread,
// in the caller's floating-point environment, whatever environment TBB's own contexts captured earlier (Embree's
// build, for one, leaves flush-to-zero and denormals-are-zero in them).
#include <gtest/gtest.h>

#include <xmmintrin.h>

#include <tbb/task_arena.h>

#include <cstdint>
#include <vector>

#include "rayaccel/accel/registry.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {
namespace {

constexpr unsigned kFlushToZeroAndDenormalsAreZero = 0x8040;

/// Sets MXCSR for the object's lifetime.
class ScopedCsr {
 public:
  explicit ScopedCsr(unsigned csr) : saved_(_mm_getcsr()) { _mm_setcsr(csr); }
  ~ScopedCsr() { _mm_setcsr(saved_); }

 private:
  unsigned saved_;
};

/// One floor triangle on y = 0 and rays from 2^-149 below it going straight up: with subnormals they hit it at
/// t = 2^-149; with denormals-are-zero the origin reads as lying on the plane and nothing is hit.
Scene floor_scene() {
  TriangleMesh mesh;
  mesh.vertices = {{-10.0f, 0.0f, -10.0f}, {10.0f, 0.0f, -10.0f}, {0.0f, 0.0f, 10.0f}};
  mesh.triangles = {{0, 1, 2}};
  return Scene::from_mesh(std::move(mesh), "floor");
}

std::vector<Ray> rays_from_below() {
  std::vector<Ray> rays(256);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    rays[i].origin = {-2.0f + 0.015f * float(i), -0x1p-149f, 1.0f};
    rays[i].direction = {0.0f, 1.0f, 0.0f};
  }
  return rays;
}

void expect_batches_match_single_calls(const Accelerator& accel, const std::vector<Ray>& rays, bool expect_found) {
  std::vector<Hit> hits(rays.size());
  accel.intersect(rays, hits);
  std::vector<std::uint8_t> occluded(rays.size());
  accel.occluded(rays, occluded);
  std::vector<Hit> packet_hits(rays.size());
  accel.intersect_packets(rays, packet_hits);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hit single = accel.intersect(rays[i]);
    ASSERT_EQ(single.found(), expect_found) << "ray " << i;
    EXPECT_EQ(hits[i].found(), single.found()) << "ray " << i;
    EXPECT_EQ(hits[i].t, single.t) << "ray " << i;
    EXPECT_EQ(packet_hits[i].found(), single.found()) << "packet ray " << i;
    EXPECT_EQ(packet_hits[i].t, single.t) << "packet ray " << i;
    EXPECT_EQ(occluded[i] != 0, accel.occluded(rays[i])) << "ray " << i;
  }
}

TEST(BatchFloatEnvironment, BatchesRunInTheCallersEnvironment) {
  const Scene scene = floor_scene();
  const std::vector<Ray> rays = rays_from_below();
  for (const char* spec : {"brute_force", "bvh_wide"}) {
    SCOPED_TRACE(spec);
    auto accel = make_accelerator(spec);
    accel->build(scene);
    const unsigned normal = _mm_getcsr() & ~kFlushToZeroAndDenormalsAreZero;
    // An arena first entered under FTZ/DAZ: its default context captured them.
    tbb::task_arena daz_arena(2);
    {
      const ScopedCsr daz(normal | kFlushToZeroAndDenormalsAreZero);
      daz_arena.initialize();
      daz_arena.execute([] {});
    }
    daz_arena.execute([&] {
      const ScopedCsr caller(normal);
      expect_batches_match_single_calls(*accel, rays, true);
    });
    // And the other way round: a caller with FTZ/DAZ set gets its own setting in the batch.
    tbb::task_arena normal_arena(2);
    {
      const ScopedCsr plain(normal);
      normal_arena.initialize();
      normal_arena.execute([] {});
    }
    normal_arena.execute([&] {
      const ScopedCsr caller(normal | kFlushToZeroAndDenormalsAreZero);
      expect_batches_match_single_calls(*accel, rays, false);
    });
  }
}

}  // namespace
}  // namespace rayaccel
