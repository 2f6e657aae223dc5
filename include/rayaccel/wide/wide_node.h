// Node<W>: one node of a W-wide BVH (W = 4 or 8), children's boxes stored SoA so one SIMD test covers all of them,
// and the encoding of child references (inner node or leaf of Triangle4 blocks).
#pragma once

#include <cstdint>

#include "rayaccel/core/aabb.h"

namespace rayaccel::wide {

template <int W>
struct alignas(64) Node {
  float bounds[3][2][W];   ///< 24*W bytes: [axis][lo, hi][child]; an unused child has lo = +inf, hi = -inf
  std::uint32_t child[W];  ///< 4*W bytes: node index, or kLeafBit | first block << kBlockShift | (blocks - 1)
  // W = 4: 96 + 16 bytes padded to 128; W = 8: 192 + 32 bytes padded to 256 (alignment to cache lines).
};
static_assert(sizeof(Node<4>) == 128, "Node<4> is 128 bytes");
static_assert(sizeof(Node<8>) == 256, "Node<8> is 256 bytes");

inline constexpr std::uint32_t kLeafBit = 0x80000000u;
inline constexpr std::uint32_t kBlockShift = 3;            ///< low 3 bits: block count - 1
inline constexpr std::uint32_t kMaxLeafBlocks = 8;         ///< at most 32 primitives per leaf
inline constexpr std::uint32_t kEmptyChild = 0xFFFFFFFFu;  ///< never followed: its box is empty

inline std::uint32_t leaf_first_block(std::uint32_t ref) { return (ref & ~kLeafBit) >> kBlockShift; }
inline std::uint32_t leaf_block_count(std::uint32_t ref) { return (ref & ((1u << kBlockShift) - 1)) + 1; }

/// Writes child `lane`'s box into the node's SoA bounds.
template <int W>
void set_child_bounds(Node<W>& node, int lane, const AABB& box) {
  for (int a = 0; a < 3; ++a) {
    node.bounds[a][0][lane] = box.lo[a];
    node.bounds[a][1][lane] = box.hi[a];
  }
}

/// Child `lane`'s box, read back from the node's SoA bounds.
template <int W>
AABB child_bounds(const Node<W>& node, int lane) {
  AABB box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = node.bounds[a][0][lane];
    box.hi[a] = node.bounds[a][1][lane];
  }
  return box;
}

}  // namespace rayaccel::wide
