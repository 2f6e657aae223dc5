// The instruction-set choice of bvh_wide (WideIsa): the AVX-512 build is used exactly when asked for and available,
// answers every ray exactly as the AVX2 build does, and an isa for a width it does not apply to is refused.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/scene/builtin_scenes.h"
#include "rayaccel/wide/wide_bvh.h"
#include "wide_test_helpers.h"

namespace rayaccel::wide {
namespace {

TEST(WideIsa, AvxFiveTwelveKernelsRunExactlyWhereAskedAndAvailable) {
  const Scene scene = make_builtin_scene("default");
  auto best = make_accelerator("bvh_wide:width=8");
  auto avx2 = make_accelerator("bvh_wide:width=8,isa=avx2");
  auto narrow = make_accelerator("bvh_wide:width=4");
  for (auto* a : {best.get(), avx2.get(), narrow.get()}) a->build(scene);
  EXPECT_EQ(statistics(*best)["avx512_kernels"], simd::best_isa() == simd::Isa::avx512 ? 1.0 : 0.0);
  EXPECT_EQ(statistics(*avx2)["avx512_kernels"], 0.0);
  EXPECT_EQ(statistics(*narrow)["avx512_kernels"], 0.0);
}

TEST(WideIsa, BothEightWideBuildsGiveTheSameAnswersBitForBit) {
  const Scene scene = make_builtin_scene("default");
  auto best = make_accelerator("bvh_wide:width=8");
  auto avx2 = make_accelerator("bvh_wide:width=8,isa=avx2");
  best->build(scene);
  avx2->build(scene);
  const int hits = expect_same_answers(scene, *best, *avx2, 4000, 11);
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
