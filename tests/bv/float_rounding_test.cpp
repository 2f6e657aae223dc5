// Directed rounding of doubles to floats: the result encloses the value, one ulp at most away.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "rayaccel/core/float_rounding.h"

namespace rayaccel {
namespace {

TEST(BvFloatRounding, EnclosesAndIsTight) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-150, 127);
  for (int i = 0; i < 20000; ++i) {
    const double x = std::ldexp(mantissa(rng), exponent(rng));
    const float lo = round_down_to_float(x), hi = round_up_to_float(x);
    ASSERT_LE(double(lo), x);
    ASSERT_GE(double(hi), x);
    ASSERT_LE(hi, std::nextafter(lo, std::numeric_limits<float>::infinity()));
    if (double(float(x)) == x) {
      ASSERT_EQ(lo, float(x));
      ASSERT_EQ(hi, float(x));
    }
  }
}

TEST(BvFloatRounding, SpecialValues) {
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(next_float_up(0.0f), std::numeric_limits<float>::denorm_min());
  EXPECT_EQ(next_float_up(-0.0f), std::numeric_limits<float>::denorm_min());
  EXPECT_EQ(next_float_down(0.0f), -std::numeric_limits<float>::denorm_min());
  EXPECT_EQ(next_float_up(-std::numeric_limits<float>::denorm_min()), -0.0f);
  EXPECT_EQ(next_float_up(inf), inf);
  EXPECT_EQ(next_float_down(-inf), -inf);
  EXPECT_EQ(next_float_up(std::numeric_limits<float>::max()), inf);
  EXPECT_EQ(next_float_up(1.0f), std::nextafter(1.0f, 2.0f));
  EXPECT_EQ(next_float_down(-1.0f), std::nextafter(-1.0f, -2.0f));
  EXPECT_TRUE(std::isnan(round_up_to_float(std::nan(""))));
  EXPECT_EQ(round_up_to_float(1e300), inf);
  EXPECT_EQ(round_down_to_float(1e300), std::numeric_limits<float>::max());
  EXPECT_EQ(round_down_to_float(-1e300), -inf);
}

}  // namespace
}  // namespace rayaccel

namespace rayaccel {
namespace {

// Hit::begin() uses next_float_up() for std::nextafter(t_max, +inf) on every ray: it must agree bit for bit on
// every kind of float, the void rays' t_max = -inf included.
TEST(BvFloatRounding, NextFloatUpIsNextafterTowardInfinity) {
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> values = {0.0f, -0.0f, inf, -inf, std::numeric_limits<float>::max(),
                               -std::numeric_limits<float>::max(), std::numeric_limits<float>::denorm_min(),
                               -std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::min(),
                               -std::numeric_limits<float>::min(), 1.0f, -1.0f};
  std::mt19937 rng(11);
  for (int i = 0; i < 100000; ++i) values.push_back(std::bit_cast<float>(static_cast<std::uint32_t>(rng())));
  for (float x : values) {
    if (std::isnan(x)) {
      EXPECT_TRUE(std::isnan(next_float_up(x)));
      continue;
    }
    const float expected = std::nextafter(x, inf);
    ASSERT_EQ(std::bit_cast<std::uint32_t>(next_float_up(x)), std::bit_cast<std::uint32_t>(expected)) << x;
  }
}

}  // namespace
}  // namespace rayaccel
