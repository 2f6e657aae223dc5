// CompressedNode8: an eight-wide node in 128 bytes, its child boxes quantised to 8 bits a plane in the node's own
// frame and rounded outward (Ylitie, Karras & Laine 2017; Benthin et al. 2018), decoded exactly into float boxes that
// contain the children's, so the robust slab test keeps its bound (bvh_wide's compress=1).
#pragma once

#include <cstdint>

#include "rayaccel/core/aabb.h"
#include "rayaccel/wide/wide_node.h"

namespace rayaccel::wide {

/// Child `lane`'s box is origin[a] + q[a][0][lane] * scale[a] .. origin[a] + q[a][1][lane] * scale[a] on axis a.
/// Each scale is a power of two and each origin a multiple of it, small enough that every origin + q * scale
/// (q = 0..255) is a float: the decoding is exact (no rounding in either the product or the sum, also when the two
/// are fused), so a decoded box is an ordinary float box containing the child's, and the traversal's slab test
/// (simd/box_kernel.h, Ize 2013) applies to it unchanged with its own error bound. An unused child has
/// child[lane] == kEmptyChild (its q is 0); the box test masks it out by that reference, not by its box.
struct alignas(64) CompressedNode8 {
  std::uint32_t child[8];      ///< 32 bytes, as Node<8>::child
  float origin[3];             ///< 12
  float scale[3];              ///< 12: powers of two
  std::uint8_t q[3][2][8];     ///< 48: [axis][lo, hi][child]
  std::uint8_t order[8][3];    ///< 24: Node<8>::order's 24-bit words, little-endian
};
static_assert(sizeof(CompressedNode8) == 128, "CompressedNode8 is two cache lines");

/// The child order word for `octant` (Node::order, wide_node.h), read from either layout.
template <int W>
unsigned child_order(const Node<W>& node, unsigned octant) {
  return node.order[octant];
}
inline unsigned child_order(const CompressedNode8& node, unsigned octant) {
  const std::uint8_t* b = node.order[octant];
  return static_cast<unsigned>(b[0]) | static_cast<unsigned>(b[1]) << 8 | static_cast<unsigned>(b[2]) << 16;
}

/// Quantises `node` into `out`: child references and orders copied, each used child's box rounded outward to the
/// node's grid. False (out unspecified) when a plane cannot be written exactly in that form within float range
/// (boxes beyond about 2^120 in magnitude); the caller then keeps the uncompressed nodes.
bool compress_node(const Node<8>& node, CompressedNode8& out);

/// Child `lane`'s decoded box (what the traversal tests), in float, exactly.
AABB decoded_child_bounds(const CompressedNode8& node, int lane);

}  // namespace rayaccel::wide
