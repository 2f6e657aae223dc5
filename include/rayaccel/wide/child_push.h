// How the traversal puts a node's hit children on its stack: with AVX-512 lanes (simd::Avx8Masked) closest-hit sorts
// them in registers with a sorting network; any-hit takes them in the node's order for the ray's octant (Fuetterling
// et al. 2017), packed with vpcompressd where the lanes have it.
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

/// Any hit: the children in `mask` (one or more) in the order word's order (Node::order[octant]): returns the first,
/// to be entered now, and pushes the others onto pending[count ..] so that the next in order is on top. With AVX-512
/// lanes the lane indices are unpacked in a register, the children permuted into order and packed by vpcompressd
/// (writes eight entries); otherwise a loop over the W positions.
template <class S, int W>
RAYACCEL_LANE_INLINE std::uint32_t push_in_octant_order(const Node<W>& node, unsigned mask, unsigned order,
                                                        std::uint32_t* pending, int& count) {
  unsigned ranked = 0;  // bit p: the child at position p was met
  if constexpr (W == 8 && requires { requires S::kMaskRegisters; }) {
    const typename S::I lanes = S::order_lanes(order);
    ranked = S::lanes_in_mask(lanes, mask);
    const int first = 31 - __builtin_clz(ranked);
    const unsigned rest = ranked ^ (1u << first);
    S::store_u32(pending + count, S::compress(rest, S::gather_lanes(lanes, S::load_u32(node.child))));
    count += __builtin_popcount(rest);
    return node.child[order_lane(order, first)];
  } else {
    for (int position = 0; position < W; ++position) ranked |= (mask >> order_lane(order, position) & 1u) << position;
    const int first = 31 - __builtin_clz(ranked);
    for (unsigned rest = ranked ^ (1u << first); rest; rest &= rest - 1) {
      pending[count++] = node.child[order_lane(order, __builtin_ctz(rest))];
    }
    return node.child[order_lane(order, first)];
  }
}
RAYACCEL_LANE_CODE_END

}  // namespace rayaccel::wide
