// The slab test of one ray against a CompressedNode8's eight child boxes: each plane decoded exactly from its 8-bit
// grid index (origin + q * scale), then simd::BoxKernel's robust test (Ize 2013) with its own error bound.
#pragma once

#include <cstddef>

#include "rayaccel/simd/box_kernel.h"
#include "rayaccel/wide/compressed_node.h"

namespace rayaccel::wide {

RAYACCEL_LANE_CODE_BEGIN
/// BoxPacket with the byte offsets of the ray's near and far planes in CompressedNode8::q (a plane is 8 bytes there,
/// 32 in Node<8>::bounds).
template <class S>
struct CompressedBoxPacket : simd::BoxPacket<S> {
  std::ptrdiff_t near_q[3], far_q[3];

  RAYACCEL_LANE_INLINE explicit CompressedBoxPacket(const PreparedRay& r) : simd::BoxPacket<S>(r) {
    for (int a = 0; a < 3; ++a) {
      near_q[a] = this->near_bytes[a] / static_cast<std::ptrdiff_t>(sizeof(float));
      far_q[a] = this->far_bytes[a] / static_cast<std::ptrdiff_t>(sizeof(float));
    }
  }
};

/// The box kernel over compressed eight-wide nodes (eight-lane sets only: Avx8, Avx8Masked).
template <class S>
struct CompressedBoxKernel {
  static_assert(S::kWidth == 8, "compressed nodes are eight wide");
  static constexpr int kWidth = 8;
  using Lanes = S;
  using Packet = CompressedBoxPacket<S>;
  using F = typename S::F;

  RAYACCEL_LANE_INLINE static Packet prepare(const PreparedRay& r) { return Packet(r); }

  /// A node's planes decoded from the grid, for simd::BoxKernel::clip_lanes.
  struct GridPlanes {
    const CompressedNode8& node;
    const Packet& ray;
    RAYACCEL_LANE_INLINE void operator()(int a, bool far, F& plane) const {
      const F q = S::load_u8(&node.q[0][0][0] + (far ? ray.far_q[a] : ray.near_q[a]));
      plane = S::add(S::mul(q, S::set1(node.scale[a])), S::set1(node.origin[a]));  // exact, fused or not
    }
  };

  /// As simd::BoxKernel::intersect_lanes, over the decoded boxes; unused children (kEmptyChild) are masked out by
  /// their reference, as their grid box is not empty.
  RAYACCEL_LANE_INLINE static unsigned intersect_lanes(const Packet& ray, const CompressedNode8& node,
                                                       float t_far_scalar, F& t_entry) {
    const unsigned met = simd::BoxKernel<S>::clip_lanes(ray, t_far_scalar, t_entry, GridPlanes{node, ray});
    return met & S::lanes_not_equal(node.child, kEmptyChild);
  }
};
RAYACCEL_LANE_CODE_END

}  // namespace rayaccel::wide
