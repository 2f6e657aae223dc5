// Per-ray mailbox (Amanatides & Woo 1987; Kirk & Arvo): the last few primitive ids one ray tested, kept on the
// stack so it is thread-safe, so a primitive referenced by several cells is not tested twice. Skipping is always
// safe: a repeated test of the same ray can only fail, since hit.t never grows. The disabled form costs nothing.
#pragma once

#include <cstdint>

#include "rayaccel/core/hit.h"

namespace rayaccel {

template <bool Enabled>
struct RayMailbox {
  static constexpr bool seen_before(std::uint32_t) { return false; }
};

template <>
struct RayMailbox<true> {
  static constexpr int kSize = 8;  // a power of two
  std::uint32_t ids[kSize] = {kInvalidPrimId, kInvalidPrimId, kInvalidPrimId, kInvalidPrimId,
                              kInvalidPrimId, kInvalidPrimId, kInvalidPrimId, kInvalidPrimId};
  int next = 0;
  /// True when `id` was recorded before; otherwise records it (evicting the oldest) and returns false.
  bool seen_before(std::uint32_t id) {
    for (std::uint32_t seen : ids) {
      if (seen == id) return true;
    }
    ids[next] = id;
    next = (next + 1) & (kSize - 1);
    return false;
  }
};

}  // namespace rayaccel
