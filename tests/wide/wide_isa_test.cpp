// The instruction-set choice of bvh_wide (WideIsa): the AVX-512 build is used exactly when asked for and available,
// answers every ray exactly as the AVX2 build does, and an isa for a width it does not apply to is refused.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/scene/builtin_scenes.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel::wide {
namespace {

std::map<std::string, double> statistics(const Accelerator& accel) {
  std::map<std::string, double> out;
  for (const auto& s : accel.build_statistics()) out[s.name] = s.value;
  return out;
}

TEST(WideIsa, AvxFiveTwelveKernelsRunExactlyWhereAskedAndAvailable) {
  const Scene scene = make_builtin_scene("default");
  auto best = make_accelerator("bvh_wide:width=8");
  auto avx2 = make_accelerator("bvh_wide:width=8,isa=avx2");
  auto narrow = make_accelerator("bvh_wide:width=4");
  for (auto* a : {best.get(), avx2.get(), narrow.get()}) a->build(scene);
  EXPECT_EQ(statistics(*best)["avx512_kernels"], cpu_has_avx512() ? 1.0 : 0.0);
  EXPECT_EQ(statistics(*avx2)["avx512_kernels"], 0.0);
  EXPECT_EQ(statistics(*narrow)["avx512_kernels"], 0.0);
}

TEST(WideIsa, BothEightWideBuildsGiveTheSameAnswersBitForBit) {
  const Scene scene = make_builtin_scene("default");
  auto best = make_accelerator("bvh_wide:width=8");
  auto avx2 = make_accelerator("bvh_wide:width=8,isa=avx2");
  best->build(scene);
  avx2->build(scene);
  const AABB box = scene.bounds();
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  auto inside = [&] {
    return Vec3{box.lo.x + u(rng) * (box.hi.x - box.lo.x), box.lo.y + u(rng) * (box.hi.y - box.lo.y),
                box.lo.z + u(rng) * (box.hi.z - box.lo.z)};
  };
  int hits = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 origin = inside();
    const Ray ray{origin, 0.0f, inside() - origin, i % 3 == 0 ? 0.5f : std::numeric_limits<float>::infinity()};
    const Hit a = best->intersect(ray);
    const Hit b = avx2->intersect(ray);
    ASSERT_EQ(a.prim_id, b.prim_id) << "ray " << i;
    ASSERT_EQ(std::memcmp(&a.t, &b.t, sizeof a.t), 0) << "ray " << i;
    ASSERT_EQ(std::memcmp(&a.u, &b.u, sizeof a.u), 0) << "ray " << i;
    ASSERT_EQ(std::memcmp(&a.v, &b.v, sizeof a.v), 0) << "ray " << i;
    ASSERT_EQ(best->occluded(ray), avx2->occluded(ray)) << "ray " << i;
    hits += a.prim_id != kInvalidPrimId ? 1 : 0;
  }
  EXPECT_GT(hits, 1000) << "rays between points of the scene box should hit often";
}

TEST(WideIsa, AnIsaForTheFourWideKernelsIsRefused) {
  try {
    make_accelerator("bvh_wide:width=4,isa=avx2");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("isa=avx2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(make_accelerator("bvh_wide:isa=avx512"), Error);  // not a choice: best or avx2
}

}  // namespace
}  // namespace rayaccel::wide
