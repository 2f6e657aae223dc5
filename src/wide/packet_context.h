// Internal to wide_bvh_packets.cpp: the query context (core/query_context.h) of one packet of eight rays, each lane
// with its own ray's rules (skip, masks, primitive switches) and the filter, for the packet traversal's leaves.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/query_context.h"

namespace rayaccel::wide {

/// The plain packet traversal's context: none (its leaves test every triangle against every ray).
struct NoPacketContext {};

template <int kLanes>
class PacketContext {
 public:
  /// The rules of rays [first, first + count) of a batch traced under `context`; lanes past `count` (the void rays
  /// of a last, partial packet, never tested) read the last ray's entries.
  PacketContext(const QueryContext& context, std::size_t first, int count) : filter_(context.filter != nullptr) {
    for (int i = 0; i < kLanes; ++i) {
      lane_[i].emplace(context, first + static_cast<std::size_t>(i < count ? i : count - 1), none_);
    }
  }
  PacketContext(const PacketContext&) = delete;  // the lanes refer to none_
  PacketContext& operator=(const PacketContext&) = delete;
  /// The lanes of `rays` whose ray may test primitive `prim_id` (asked before the triangle test).
  int allowed(std::uint32_t prim_id, int rays) const {
    int out = 0;
    for (int rest = rays; rest; rest &= rest - 1) {
      const int i = __builtin_ctz(static_cast<unsigned>(rest));
      if (lane_[i]->allows(prim_id)) out |= 1 << i;
    }
    return out;
  }
  bool has_filter() const { return filter_; }
  /// The lanes of `changed` whose new hit the filter rejects; their hits are put back to `before`.
  int reject(int changed, Hit* hits, const Hit* before) const {
    int rejected = 0;
    for (int rest = changed; rest; rest &= rest - 1) {
      const int i = __builtin_ctz(static_cast<unsigned>(rest));
      if (lane_[i]->accepts(hits[i])) continue;
      hits[i] = before[i];
      rejected |= 1 << i;
    }
    return rejected;
  }
  /// Lane i's rules, for the single-ray traversal of packets off the fast path.
  ContextStats<NoStats>& lane(int i) { return *lane_[i]; }

 private:
  NoStats none_;
  bool filter_;
  std::array<std::optional<ContextStats<NoStats>>, kLanes> lane_;
};

}  // namespace rayaccel::wide
