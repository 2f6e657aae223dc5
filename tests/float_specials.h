// The float special values tests pass as inputs (infinities and NaN), defined once: the test files compile in batches
// (tests/CMakeLists.txt, RAYACCEL_UNITY_TESTS), where a constant defined in two files of one batch would collide.
#pragma once

#include <limits>

namespace rayaccel::test_values {

inline constexpr float kInf = std::numeric_limits<float>::infinity();
inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

}  // namespace rayaccel::test_values
