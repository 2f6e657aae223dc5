// The AVX-512 lane operations the wide BVH's traversal pushes children with (simd/lanes_avx512.h): the sorting
// network against std::sort on every order of eight keys, and the sort keys' distances against their lanes'.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <numeric>
#include <random>

#include "rayaccel/simd/isa.h"
#if RAYACCEL_AVX_KERNELS
#include "rayaccel/simd/lanes_avx512.h"
#endif

namespace rayaccel::simd {
namespace {

#if RAYACCEL_AVX_KERNELS
using Lanes8 = std::array<std::int32_t, 8>;

RAYACCEL_TARGET_AVX512 __attribute__((flatten)) Lanes8 sorted_descending(const Lanes8& in) {
  Lanes8 out;
  const __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(in.data()));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out.data()), Avx8Masked::sort_descending(v));
  return out;
}

/// The sorted keys of `t`'s lanes in `mask`: each key's lane (low three bits) and the distance it stands for.
struct SortedKeys {
  std::array<int, 8> lane;
  std::array<float, 8> distance;
};
RAYACCEL_TARGET_AVX512 __attribute__((flatten)) SortedKeys sorted_keys(const std::array<float, 8>& t, unsigned mask) {
  const __m256i keys = Avx8Masked::sort_descending(Avx8Masked::lane_keys(_mm256_loadu_ps(t.data()), mask));
  std::array<std::int32_t, 8> k, d;
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(k.data()), keys);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(d.data()), Avx8Masked::key_distance_bits(keys));
  SortedKeys out;
  for (int i = 0; i < 8; ++i) {
    out.lane[i] = k[i] & 7;
    std::memcpy(&out.distance[i], &d[i], sizeof(float));
  }
  return out;
}

TEST(LanesAvx512, SortingNetworkSortsEveryOrderOfEightKeys) {
  if (!cpu_has_avx512()) GTEST_SKIP() << "this CPU has no AVX-512";
  Lanes8 keys;
  std::iota(keys.begin(), keys.end(), -3);
  keys[7] = std::numeric_limits<std::int32_t>::min();  // the key of a lane not met
  std::sort(keys.begin(), keys.end());
  Lanes8 expected = keys;
  std::sort(expected.begin(), expected.end(), std::greater<>());
  int orders = 0;
  do {
    ASSERT_EQ(sorted_descending(keys), expected) << "order " << orders;
    ++orders;
  } while (std::next_permutation(keys.begin(), keys.end()));
  EXPECT_EQ(orders, 40320);
}

TEST(LanesAvx512, KeysOrderTheLanesMetAndNeverRaiseTheirDistance) {
  if (!cpu_has_avx512()) GTEST_SKIP() << "this CPU has no AVX-512";
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> mantissa(1.0f, 2.0f);
  std::uniform_int_distribution<int> exponent(-140, 120), pick(0, 9);
  for (int trial = 0; trial < 20000; ++trial) {
    std::array<float, 8> t;
    for (float& x : t) {
      const int kind = pick(rng);
      x = kind == 0 ? 0.0f : kind == 1 ? -0.0f : kind == 2 ? std::numeric_limits<float>::infinity()
                                                         : std::ldexp(mantissa(rng), exponent(rng));
      if (kind == 3) x = -x;  // entry distances below 0 (t_min < 0, or an origin shift)
    }
    const auto mask = static_cast<unsigned>(rng() & 0xFF);
    const SortedKeys s = sorted_keys(t, mask);
    const int met = __builtin_popcount(mask);
    for (int i = 0; i < met; ++i) {
      const int lane = s.lane[i];
      ASSERT_TRUE(mask >> lane & 1) << "trial " << trial << ": lane " << lane << " was not met";
      ASSERT_LE(s.distance[i], t[lane]) << "trial " << trial;  // a key never raises its lane's distance
      float eight_below = t[lane];
      for (int k = 0; k < 8; ++k) eight_below = std::nextafter(eight_below, -INFINITY);
      ASSERT_GT(s.distance[i], eight_below) << "trial " << trial << ": more than 7 floats below " << t[lane];
      if (i > 0) {
        ASSERT_GE(s.distance[i - 1], s.distance[i]) << "trial " << trial << ": not farthest first";
      }
    }
    for (int i = 0; i < met; ++i) {
      for (int j = i + 1; j < met; ++j) ASSERT_NE(s.lane[i], s.lane[j]) << "trial " << trial;
    }
  }
}
#endif

}  // namespace
}  // namespace rayaccel::simd
