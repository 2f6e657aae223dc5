// Hit: the closest-hit record {t, prim_id, u, v}, with barycentrics as in Embree: p = (1-u-v)*v0 + u*v1 + v*v2.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "rayaccel/core/float_rounding.h"
#include "rayaccel/core/ray.h"

namespace rayaccel {

inline constexpr std::uint32_t kInvalidPrimId = 0xFFFFFFFFu;

struct Hit {
  /// While tracing: the exclusive upper bound of t for further hits (see begin()). After finish(): the hit
  /// distance, or +inf for a miss.
  float t = std::numeric_limits<float>::infinity();
  std::uint32_t prim_id = kInvalidPrimId;
  float u = 0.0f;
  float v = 0.0f;

  bool found() const { return prim_id != kInvalidPrimId; }

  /// A hit counts when t_min < t <= t_max (Embree's rule). Tracing keeps one exclusive bound, hit.t, which starts
  /// just above t_max and shrinks to each closer hit, so "t < hit.t" is the only far test a kernel needs, and of
  /// two hits at the same t the first found is kept.
  static Hit begin(const PreparedRay& ray) {
    Hit h;
    h.t = next_float_up(ray.t_max);  // as std::nextafter(t_max, +inf), without the libm call per ray
    return h;
  }
  /// Turns a tracing record into the published form: misses get t = +inf and u = v = 0.
  void finish() {
    if (!found()) { t = std::numeric_limits<float>::infinity(); u = 0.0f; v = 0.0f; }
  }
};
static_assert(sizeof(Hit) == 16, "Hit is the 16-byte record of the .hits file");

}  // namespace rayaccel
