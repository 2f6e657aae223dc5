// Tests of the bench's reference check (apps/rayaccel/bench_check.cpp): an honest structure passes, and
// deliberately wrong ones fail it: another primitive at a nearly equal t, a hit/miss flip, every 10th hit dropped, a
// neighbouring primitive, and t, u, v that are not the kernel's. With and without Embree as the reference, with a
// reference that is wrong the same way as the structure (the brute-force sample catches it), and Embree's own row
// under the foreign-kernel rule. Light packet workloads are checked through occluded_packets().
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include "bench.h"
#include "rayaccel/accel/brute_force.h"
#include "rayaccel/compare/embree_accelerator.h"

namespace rayaccel::cli {
namespace {

/// Brute force's answers passed through `corrupt` (ray index, hit), and its occluded_packets() answers through
/// `corrupt_packets` (position in the batch, answer): a structure that is wrong on purpose.
class CorruptedBruteForce final : public Accelerator {
 public:
  explicit CorruptedBruteForce(std::function<void(const Ray&, Hit&)> corrupt,
                               std::function<void(std::size_t, std::uint8_t&)> corrupt_packets = {})
      : corrupt_(std::move(corrupt)), corrupt_packets_(std::move(corrupt_packets)) {}
  void build(const Scene& scene) override { oracle_.build(scene); }
  Hit intersect(const Ray& ray) const override {
    Hit h = oracle_.intersect(ray);
    corrupt_(ray, h);
    return h;
  }
  Hit intersect(const Ray& ray, TraversalStats&) const override { return intersect(ray); }
  bool occluded(const Ray& ray) const override { return oracle_.occluded(ray); }
  bool occluded(const Ray& ray, TraversalStats&) const override { return occluded(ray); }
  void intersect(std::span<const Ray> rays, std::span<Hit> hits, std::span<TraversalStats>) const override {
    for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = intersect(rays[i]);
  }
  void occluded(std::span<const Ray> rays, std::span<std::uint8_t> out, std::span<TraversalStats>) const override {
    for (std::size_t i = 0; i < rays.size(); ++i) out[i] = occluded(rays[i]) ? 1 : 0;
  }
  void occluded_packets(std::span<const Ray> rays, std::span<std::uint8_t> out) const override {
    occluded(rays, out, {});
    if (corrupt_packets_) {
      for (std::size_t i = 0; i < rays.size(); ++i) corrupt_packets_(i, out[i]);
    }
  }
  /// Queries with a context: brute force's, or, after ignore_context(), the plain queries' answers (a structure that
  /// ignores the skip).
  void intersect(const QueryContext& context, std::span<const Ray> rays, std::span<Hit> hits) const override {
    if (!ignore_context_) return oracle_.intersect(context, rays, hits);
    intersect(rays, hits, {});
  }
  void occluded(const QueryContext& context, std::span<const Ray> rays, std::span<std::uint8_t> out) const override {
    if (!ignore_context_) return oracle_.occluded(context, rays, out);
    occluded(rays, out, {});
  }
  using Accelerator::intersect;
  using Accelerator::occluded;
  void ignore_context() { ignore_context_ = true; }
  std::size_t memory_bytes() const override { return 0; }
  std::vector<std::string> validate() const override { return {}; }

 private:
  bool ignore_context_ = false;
  BruteForce oracle_;
  std::function<void(const Ray&, Hit&)> corrupt_;
  std::function<void(std::size_t, std::uint8_t&)> corrupt_packets_;
};

/// Two parallel unit squares facing the rays, at z = 0 (prims 0, 1) and z = -0.00005 (prims 2, 3): from z = 1 the
/// farther one is hit at a t within 1e-4 relative of the nearer one, the tolerance the old check accepted.
Scene two_close_layers() {
  TriangleMesh mesh;
  for (const float z : {0.0f, -0.00005f}) {
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), {{-1, -1, z}, {1, -1, z}, {1, 1, z}, {-1, 1, z}});
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.triangles.push_back({base, base + 2, base + 3});
  }
  return Scene::from_mesh(std::move(mesh), "layers");
}

std::vector<Workload> straight_down_rays() {
  Workload w;
  w.kind = RayKind::primary;
  for (int i = 0; i < 64; ++i) {
    const float x = -0.9f + 1.8f * static_cast<float>(i % 8) / 7.0f + 0.001f;
    const float y = -0.9f + 1.8f * static_cast<float>(i / 8) / 7.0f;
    w.rays.push_back({{x, y, 1.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, 10.0f});
  }
  return {w};
}

/// Mismatches the check finds in `accel` on the straight-down rays, with Embree as the reference when `embree`.
std::size_t mismatches(const Accelerator& accel, const Scene& scene, const std::vector<Workload>& workloads,
                       const Accelerator* embree, std::size_t sample_size = 2000) {
  const ReferenceCheck check(scene, workloads, embree, sample_size);
  std::vector<KindResult> kinds(workloads.size());
  check.check(accel, kinds);
  return kinds[0].mismatches;
}

/// Replaces a hit by the farther layer's triangle under the ray, with its own kernel t, u, v: within 1e-4 relative
/// t of the right answer, not a tie.
std::function<void(const Ray&, Hit&)> farther_layer(const Scene& scene) {
  return [&scene](const Ray& ray, Hit& h) {
    const PreparedRay prepared(ray);
    Hit farther = Hit::begin(prepared);
    for (std::uint32_t prim : {2u, 3u}) scene.intersect(prim, prepared, farther);
    h = farther;
  };
}

/// Drops the 1st, 11th, 21st, ... hit asked for (7 of the 64 straight-down rays, traced one by one in order).
std::function<void(const Ray&, Hit&)> every_tenth_dropped() {
  return [calls = std::size_t{0}](const Ray&, Hit& h) mutable {
    if (calls++ % 10 == 0) h = Hit{};
  };
}

void expect_check_catches_wrong_structures(const Accelerator* embree) {
  const Scene scene = two_close_layers();
  const std::vector<Workload> workloads = straight_down_rays();
  const auto run = [&](std::function<void(const Ray&, Hit&)> corrupt) {
    CorruptedBruteForce accel(std::move(corrupt));
    accel.build(scene);
    return mismatches(accel, scene, workloads, embree);
  };
  EXPECT_EQ(run([](const Ray&, Hit&) {}), 0u) << "an honest structure passes";
  EXPECT_EQ(run(farther_layer(scene)), 64u);
  EXPECT_EQ(run(every_tenth_dropped()), 7u);
  // The other triangle of the same square, which the ray does not cross, with the right t, u, v.
  EXPECT_EQ(run([](const Ray&, Hit& h) { h.prim_id ^= 1u; }), 64u);
  // A miss reported for one ray.
  EXPECT_EQ(run([](const Ray& ray, Hit& h) {
              if (ray.origin.x < -0.8f && ray.origin.y < -0.8f) h = Hit{};
            }),
            1u);
  // The right primitive with u one ulp off, or t one ulp off: not the kernel's answer.
  EXPECT_EQ(run([](const Ray&, Hit& h) { h.u = std::nextafter(h.u, 2.0f); }), 64u);
  EXPECT_EQ(run([](const Ray&, Hit& h) { h.t = std::nextafter(h.t, 0.0f); }), 64u);
}

TEST(BenchCheck, CatchesWrongStructuresAgainstBruteForce) { expect_check_catches_wrong_structures(nullptr); }

#ifdef RAYACCEL_HAVE_EMBREE
TEST(BenchCheck, CatchesWrongStructuresAgainstEmbree) {
  EmbreeAccelerator embree;
  const Scene scene = two_close_layers();
  embree.build(scene);
  expect_check_catches_wrong_structures(&embree);
}

TEST(BenchCheck, EmbreesOwnRowIsCheckedAsAForeignKernel) {
  const Scene scene = two_close_layers();
  const std::vector<Workload> workloads = straight_down_rays();
  EmbreeAccelerator embree;
  embree.build(scene);
  const ReferenceCheck check(scene, workloads, &embree, 2000);
  const auto differences = [&](const Accelerator& row) {
    std::vector<KindResult> kinds(workloads.size());
    check.check_foreign(row, kinds);
    EXPECT_EQ(kinds[0].checked, 64u);
    return kinds[0].foreign_differences;
  };
  EXPECT_EQ(differences(embree), 0u) << "Embree itself, with its own rounding, passes";
  const auto corrupted = [&](std::function<void(const Ray&, Hit&)> corrupt) {
    CorruptedBruteForce row(std::move(corrupt));
    row.build(scene);
    return differences(row);
  };
  EXPECT_EQ(corrupted(every_tenth_dropped()), 7u);
  // Another kernel's rounding in t is allowed; a t 0.1% off is not.
  EXPECT_EQ(corrupted([](const Ray&, Hit& h) { h.t = std::nextafter(h.t, 0.0f); }), 0u);
  EXPECT_EQ(corrupted([](const Ray&, Hit& h) { h.t *= 1.001f; }), 64u);
}
#endif

/// Light packet workloads are traced with occluded_packets(): a structure whose packets flip the first ray of every
/// packet fails there (8 of the 64 rays) while its single-ray answers pass as light rays.
void expect_check_catches_wrong_occlusion_packets(const Accelerator* embree) {
  const Scene scene = two_close_layers();
  std::vector<Workload> workloads = straight_down_rays();
  CorruptedBruteForce accel([](const Ray&, Hit&) {}, [](std::size_t i, std::uint8_t& o) {
    if (i % 8 == 0) o ^= 1;
  });
  accel.build(scene);
  workloads[0].kind = RayKind::light_packet;
  EXPECT_EQ(mismatches(accel, scene, workloads, embree), 8u);
  workloads[0].kind = RayKind::light;
  EXPECT_EQ(mismatches(accel, scene, workloads, embree), 0u);
  CorruptedBruteForce honest([](const Ray&, Hit&) {});
  honest.build(scene);
  workloads[0].kind = RayKind::light_packet;
  EXPECT_EQ(mismatches(honest, scene, workloads, embree), 0u) << "an honest structure passes";
}

TEST(BenchCheck, CatchesWrongOcclusionPacketsAgainstBruteForce) {
  expect_check_catches_wrong_occlusion_packets(nullptr);
}

#ifdef RAYACCEL_HAVE_EMBREE
TEST(BenchCheck, CatchesWrongOcclusionPacketsAgainstEmbree) {
  EmbreeAccelerator embree;
  const Scene scene = two_close_layers();
  embree.build(scene);
  expect_check_catches_wrong_occlusion_packets(&embree);
}
#endif

/// The _skip kinds are traced and checked under their context: each straight-down ray skips the near layer's triangle
/// it crosses, so the right answer is the farther layer, and a structure that ignores the skip fails on every ray.
void expect_check_catches_ignored_skips(const Accelerator* embree) {
  const Scene scene = two_close_layers();
  std::vector<Workload> workloads = straight_down_rays();
  workloads[0].kind = RayKind::diffuse_skip;
  BruteForce oracle;
  oracle.build(scene);
  for (const Ray& ray : workloads[0].rays) workloads[0].skip.push_back(oracle.intersect(ray).prim_id);
  CorruptedBruteForce honest([](const Ray&, Hit&) {});
  honest.build(scene);
  EXPECT_EQ(mismatches(honest, scene, workloads, embree), 0u) << "an honest structure passes";
  CorruptedBruteForce ignoring([](const Ray&, Hit&) {});
  ignoring.ignore_context();
  ignoring.build(scene);
  EXPECT_EQ(mismatches(ignoring, scene, workloads, embree), 64u);
  workloads[0].kind = RayKind::occlusion_skip;  // both layers lie within reach: occluded either way
  EXPECT_EQ(mismatches(ignoring, scene, workloads, embree), 0u);
}

TEST(BenchCheck, CatchesStructuresThatIgnoreTheSkipAgainstBruteForce) { expect_check_catches_ignored_skips(nullptr); }

#ifdef RAYACCEL_HAVE_EMBREE
TEST(BenchCheck, CatchesStructuresThatIgnoreTheSkipAgainstEmbreesFilter) {
  EmbreeAccelerator embree(EmbreeOptions{0, EmbreeBuildQuality::medium, false, true});
  const Scene scene = two_close_layers();
  embree.build(scene);
  expect_check_catches_ignored_skips(&embree);
}
#endif

TEST(BenchCheck, BruteForceSampleCatchesAStructureWrongLikeItsReference) {
  // A reference that names the farther layer, as Embree would if its kernel were wrong there, and a structure
  // wrong the same way: they agree on every ray, so only brute force's sample (10 of the 64 rays) catches them.
  const Scene scene = two_close_layers();
  const std::vector<Workload> workloads = straight_down_rays();
  CorruptedBruteForce reference(farther_layer(scene));
  reference.build(scene);
  CorruptedBruteForce accel(farther_layer(scene));
  accel.build(scene);
  EXPECT_EQ(mismatches(accel, scene, workloads, &reference, 10), 10u);
  BruteForce honest;
  honest.build(scene);
  EXPECT_EQ(mismatches(honest, scene, workloads, &reference, 10), 0u) << "an honest structure passes";
}

TEST(BenchCheck, KernelFaultNamesWhatDiffers) {
  const Scene scene = two_close_layers();
  const Ray ray{{0.25f, 0.1f, 1.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, 10.0f};
  BruteForce oracle;
  oracle.build(scene);
  Hit h = oracle.intersect(ray);
  ASSERT_TRUE(h.found());
  EXPECT_EQ(kernel_fault(scene, ray, h), "");
  EXPECT_EQ(kernel_fault(scene, ray, Hit{}), "");
  Hit bad_miss;
  bad_miss.t = 3.0f;
  EXPECT_NE(kernel_fault(scene, ray, bad_miss), "");
  Hit wrong_prim = h;
  wrong_prim.prim_id = 99;
  EXPECT_NE(kernel_fault(scene, ray, wrong_prim).find("99"), std::string::npos);
  Hit not_hit = h;
  not_hit.prim_id = h.prim_id ^ 1u;  // the other triangle of the same square: the ray misses it
  EXPECT_NE(kernel_fault(scene, ray, not_hit).find("not hit"), std::string::npos);
}

}  // namespace
}  // namespace rayaccel::cli
