// How the traversal puts a node's hit children on its stack with AVX-512 lanes (simd::Avx8Masked), with no branch per
// child: closest-hit sorts them in registers with a sorting network, any-hit packs them with vpcompressd.
#pragma once

#include <cstdint>

#include "rayaccel/simd/lane_set.h"
#include "rayaccel/wide/wide_node.h"

namespace rayaccel::wide {

/// A closest-hit stack entry: a subtree and its entry distance (skipped on pop when beyond the closest hit).
struct StackEntry {
  std::uint32_t ref;
  float t_entry;
};

RAYACCEL_LANE_CODE_BEGIN
/// Closest hit: pushes the children in `mask` (two or more) farthest first onto stack[top ..] and returns the nearest,
/// which is not left on the stack. Writes eight entries from stack[top] (the stack has that room). A pushed entry
/// distance is its lane's, at most 7 ulps lower (the sort key's, simd::Avx8Masked::lane_keys): a lower entry only
/// keeps a subtree longer, so no hit is lost.
template <class S>
RAYACCEL_LANE_INLINE std::uint32_t push_sorted(const Node<8>& node, unsigned mask, const typename S::F& t_entry,
                                               StackEntry* stack, int& top) {
  using I = typename S::I;
  const I sorted = S::sort_descending(S::lane_keys(t_entry, mask));
  const I refs = S::gather_lanes(sorted, S::load_u32(node.child));
  const I distances = S::key_distance_bits(sorted);
  auto* out = reinterpret_cast<std::uint32_t*>(stack + top);
  S::store_u32(out, S::interleave_low(refs, distances));
  S::store_u32(out + 8, S::interleave_high(refs, distances));
  const int nearest = __builtin_popcount(mask) - 1;
  top += nearest;
  return S::extract_u32(refs, nearest);
}

/// Any hit: pushes the children in `mask` (one or more) but the lowest lane onto pending[count ..] in lane order and
/// returns the lowest lane's, to be entered first (the order of the scalar loop). Writes eight entries.
template <class S>
RAYACCEL_LANE_INLINE std::uint32_t push_in_lane_order(const Node<8>& node, unsigned mask, std::uint32_t* pending,
                                                      int& count) {
  const unsigned rest = mask & (mask - 1);
  S::store_u32(pending + count, S::compress(rest, S::load_u32(node.child)));
  count += __builtin_popcount(rest);
  return node.child[__builtin_ctz(mask)];
}
RAYACCEL_LANE_CODE_END

}  // namespace rayaccel::wide
