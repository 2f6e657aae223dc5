// Node<W>: one node of a W-wide BVH (W = 4 or 8), children's boxes stored SoA so one SIMD test covers all of them,
// the encoding of child references (inner node or leaf of Triangle4 blocks), and the per-octant child order of
// any-hit traversal (Fuetterling et al. 2017, "Accelerated single ray tracing for wide vector units").
#pragma once

#include <cstdint>
#include <limits>
#include <type_traits>

#include "rayaccel/core/aabb.h"

namespace rayaccel::wide {

template <int W>
struct alignas(64) Node {
  float bounds[3][2][W];   ///< 24*W bytes: [axis][lo, hi][child]; an unused child has lo = +inf, hi = -inf
  std::uint32_t child[W];  ///< 4*W bytes: node index, or kLeafBit | first block << kBlockShift | (blocks - 1)
  /// Per ray octant (PreparedRay::negative as bits 0-2), the order in which any-hit traversal takes the children,
  /// packed three bits a position: bits 3p..3p+2 hold the lane taken at rank W-1-p, so position W-1 is entered first
  /// (see set_child_order). Only an order: any permutation of the lanes gives the same answers.
  std::conditional_t<W == 8, std::uint32_t, std::uint16_t> order[8];
  // W = 4: 96 + 16 + 16 bytes; W = 8: 192 + 32 + 32 bytes: whole cache lines.
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

/// The lane at position `position` of an order word (position W-1 is entered first, position 0 last).
inline unsigned order_lane(unsigned order, int position) { return (order >> (3 * position)) & 7u; }

/// The octant of a direction as Node::order indexes it: bit a set where component a has its sign bit set.
inline unsigned ray_octant(const int negative[3]) {
  return static_cast<unsigned>(negative[0]) | static_cast<unsigned>(negative[1]) << 1 |
         static_cast<unsigned>(negative[2]) << 2;
}

/// Fills node.order from its child boxes: for each octant, the children by the projection of their box centres on
/// the octant's diagonal (-1 or +1 on each axis), farthest first, ties in lane order, unused lanes last. Farthest
/// first, as an any-hit ray that leaves a surface meets that surface's subtree first along the ray and finds no hit
/// there (visits per ray against lane order and nearest first: docs/benchmark-history.md, step 29).
template <int W>
void set_child_order(Node<W>& node) {
  for (unsigned octant = 0; octant < 8; ++octant) {
    float key[W];
    int lanes[W];
    for (int lane = 0; lane < W; ++lane) {
      lanes[lane] = lane;
      float k = 0.0f;
      for (int a = 0; a < 3; ++a) {
        const float centre = node.bounds[a][0][lane] + node.bounds[a][1][lane];
        k += (octant >> a & 1u) ? centre : -centre;  // the farthest along the diagonal has the smallest key
      }
      // Unused lanes (lo = +inf, hi = -inf) and unbounded boxes give NaN: last, and in lane order.
      key[lane] = k == k ? k : std::numeric_limits<float>::infinity();
    }
    // Insertion sort, stable: at most eight lanes.
    for (int i = 1; i < W; ++i) {
      const int lane = lanes[i];
      int j = i;
      for (; j > 0 && key[lanes[j - 1]] > key[lane]; --j) lanes[j] = lanes[j - 1];
      lanes[j] = lane;
    }
    unsigned word = 0;
    for (int rank = 0; rank < W; ++rank) word |= static_cast<unsigned>(lanes[rank]) << (3 * (W - 1 - rank));
    node.order[octant] = static_cast<std::remove_reference_t<decltype(node.order[0])>>(word);
  }
}

/// True when every order word of the node is a permutation of its W lanes (a loaded file's may not be).
template <int W>
bool child_order_is_permutation(const Node<W>& node) {
  for (unsigned word : node.order) {
    unsigned seen = 0;
    for (int position = 0; position < W; ++position) seen |= 1u << order_lane(word, position);
    if (seen != (1u << W) - 1 || (word >> (3 * W)) != 0) return false;
  }
  return true;
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
