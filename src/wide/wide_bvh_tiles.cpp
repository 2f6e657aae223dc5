// A beam's tile of up to eight 8-ray packets traced through the eight-wide BVH together: each node's children are
// culled for the whole tile by its frustum (Reshetov, Soupikov & Hurley 2005; Wald et al. 2006, frustum culling),
// then tested packet by packet with the packet traversal's per-lane box test (Wald et al. 2014), the tile's rays
// sharing one node fetch, one child order and one stack. Triangles are tested per packet with the single-ray
// kernels' float operations; rays whose hit may be a tie in t are named for the caller to trace alone.
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <new>
#include <string>
#include <type_traits>

#include "packet_lanes.h"
#include "rayaccel/core/error.h"
#include "rayaccel/wide/beam_frustum.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel::wide {

namespace {
constexpr int kTilePackets = 8;
}  // namespace

#if RAYACCEL_AVX_KERNELS
RAYACCEL_LANE_CODE_BEGIN

template <class S>
RAYACCEL_LANE_INLINE int WideBvh::trace_tile(std::uint32_t start, const BeamFrustum& frustum, const Ray* rays,
                                             int count, Hit* hits, std::uint64_t& ties_out, bool prove) const {
  using F = typename S::F;
  const int packets = count / kPacketSize;
  // Every packet prepared; a packet joins the tile when it is on the fast path, proven inside the frustum (`prove`)
  // and has the direction signs of the first that joined in every ray (each axis's near plane the same in every lane
  // of every packet); the others are refused, left to the caller.
  alignas(PacketLanes<S>) unsigned char storage[kTilePackets][sizeof(PacketLanes<S>)];
  PacketLanes<S>* lanes[kTilePackets];
  int near_offset[3] = {-1, -1, -1};
  std::uint64_t active = 0;
  int refused = 0;
  for (int p = 0; p < packets; ++p) {
    lanes[p] = new (storage[p]) PacketLanes<S>(rays + p * kPacketSize);
    const PacketLanes<S>& in = *lanes[p];
    if (!in.active) continue;
    bool joins = in.fast && (!prove || (holds_in_lanes<S>(frustum, in.origin, in.direction, in.t_min) & in.active) ==
                                           in.active);
    int offset[3];
    for (int a = 0; a < 3 && joins; ++a) {
      const int negative = S::movemask(in.direction[a]) & in.active;
      offset[a] = negative ? 1 : 0;
      joins = (negative == 0 || negative == in.active) && (near_offset[a] < 0 || near_offset[a] == offset[a]);
    }
    if (!joins) {
      refused |= 1 << p;
      continue;
    }
    for (int a = 0; a < 3; ++a) near_offset[a] = offset[a];
    active |= std::uint64_t(in.active) << (p * kPacketSize);
  }
  static_assert(std::is_trivially_destructible_v<PacketLanes<S>>, "prepared lanes are left in place");
  std::array<std::array<Hit, kPacketSize>, kTilePackets> hit;
  F far_bound[kTilePackets];
  int ties[kTilePackets] = {};
  for (int p = 0; p < packets; ++p) {
    for (int i = 0; i < kPacketSize; ++i) hit[p][i].t = lanes[p]->far[i];
    far_bound[p] = S::load(lanes[p]->far);
  }
  if (active) {
    for (int a = 0; a < 3; ++a) near_offset[a] = std::max(near_offset[a], 0);
    const F infinity = S::set1(std::numeric_limits<float>::infinity());
    // A child's box (its near and far planes, each broadcast) against the rays `bits` of packet p, as the packet
    // traversal's box test: the rays that meet it; `nearest` lowered to their entries (lane by lane).
    const auto meet_box = [&](const F near_plane[3], const F far_plane[3], int p, int bits, F& nearest)
                              RAYACCEL_LANE_LAMBDA {
      F t_near, meets;
      slab_meets<S>(*lanes[p], near_plane, far_plane, far_bound[p], t_near, meets);
      meets = S::bit_and(meets, S::lanes_from_bits(bits));
      nearest = S::min(nearest, S::blend(infinity, t_near, meets));
      return S::movemask(meets);
    };
    // Every triangle of leaf `ref` against the rays `bits` of packet p.
    const auto test_leaf = [&](std::uint32_t ref, int p, int bits) RAYACCEL_LANE_LAMBDA {
      const PacketLanes<S>& in = *lanes[p];
      const Ray* packet_rays = rays + p * kPacketSize;
      const std::uint32_t end = leaf_first_block(ref) + leaf_block_count(ref);
      for (std::uint32_t b = leaf_first_block(ref); b < end; ++b) {
        const simd::Triangle4& block = blocks_[b];
        for (int j = 0; j < 4 && block.prim_id[j] != kInvalidPrimId; ++j) {  // padding only at the end
          intersect_triangle_rays<S, true>(in.triangle, packet_rays, bits, in.axes, block, j, hit[p].data(),
                                           far_bound[p], &ties[p]);
        }
      }
    };
    const auto packet_bits = [](std::uint64_t tile_rays, int p) { return int(tile_rays >> (p * kPacketSize) & 0xff); };

    struct Entry {
      std::uint32_t ref;
      float t_entry;        ///< the nearest entry of any of its rays
      std::uint64_t rays;   ///< bit 8p + i: lane i of packet p met the subtree's box
      std::uint32_t parent;  ///< the node holding its box, as child `lane`
      int lane;
    };
    const auto load_planes = [&](const Node<kPacketSize>& node, int c, F near_plane[3], F far_plane[3])
                                 RAYACCEL_LANE_LAMBDA {
      for (int a = 0; a < 3; ++a) {
        near_plane[a] = S::broadcast(&node.bounds[a][near_offset[a]][c]);
        far_plane[a] = S::broadcast(&node.bounds[a][1 - near_offset[a]][c]);
      }
    };
    Entry stack[kStackSize];
    int top = 0;
    std::uint32_t ref = start;
    std::uint64_t tile_rays = active;
    for (;;) {
      if (ref & kLeafBit) {
        for (int p = 0; p < packets; ++p) {
          if (const int bits = packet_bits(tile_rays, p)) test_leaf(ref, p, bits);
        }
      } else {
        const Node<kPacketSize>& node = nodes8_[ref];
        // The children the frustum may meet, then each packet's rays against them; nearest entry first.
        int met[kPacketSize];
        float nearest[kPacketSize];
        std::uint64_t child_rays[kPacketSize];
        int met_count = 0;
        for (unsigned kids = unsigned(frustum_child_lanes<S, kPacketSize>(frustum, node)); kids; kids &= kids - 1) {
          const int c = __builtin_ctz(kids);
          F near_plane[3], far_plane[3];
          load_planes(node, c, near_plane, far_plane);
          F entries = infinity;
          std::uint64_t met_rays = 0;
          for (int p = 0; p < packets; ++p) {
            if (const int bits = packet_bits(tile_rays, p)) {
              met_rays |= std::uint64_t(meet_box(near_plane, far_plane, p, bits, entries)) << (p * kPacketSize);
            }
          }
          if (!met_rays) continue;
          const float d = S::horizontal_min(entries);
          // Insertion by nearest entry, farthest first, so the nearest is taken from the end.
          int k = met_count++;
          for (; k > 0 && nearest[met[k - 1]] < d; --k) met[k] = met[k - 1];
          met[k] = c;
          nearest[c] = d;
          child_rays[c] = met_rays;
        }
        if (met_count > 0) {
          for (int k = 0; k < met_count - 1; ++k) {
            const int c = met[k];
            stack[top++] = {node.child[c], nearest[c], child_rays[c], ref, c};
          }
          const int c = met[met_count - 1];
          ref = node.child[c];
          tile_rays = child_rays[c];
          continue;
        }
      }
      // Pop the next subtree some of whose rays may still have a hit there: their closest hit is not nearer than the
      // subtree's nearest entry (a ray's own entry is no nearer, so no hit is lost).
      for (;;) {
        if (top == 0) {
          for (int p = 0; p < packets; ++p) {
            if (refused >> p & 1) continue;
            for (int i = 0; i < kPacketSize; ++i) {
              hits[p * kPacketSize + i] = hit[p][i].found() ? hit[p][i] : Hit{};
            }
            ties_out |= std::uint64_t(ties[p] & lanes[p]->active) << (p * kPacketSize);
          }
          return refused;
        }
        const Entry& e = stack[--top];
        std::uint64_t still = 0;
        if (e.ref & kLeafBit) {
          // A leaf: its box again against the rays' closest hits now, lane by lane, before its triangles.
          F near_plane[3], far_plane[3];
          load_planes(nodes8_[e.parent], e.lane, near_plane, far_plane);
          F unused = infinity;
          for (int p = 0; p < packets; ++p) {
            if (const int bits = packet_bits(e.rays, p)) {
              still |= std::uint64_t(meet_box(near_plane, far_plane, p, bits, unused)) << (p * kPacketSize);
            }
          }
        } else {
          for (int p = 0; p < packets; ++p) {
            if (const int bits = packet_bits(e.rays, p)) {
              still |= std::uint64_t(bits & S::movemask(S::ge(far_bound[p], S::set1(e.t_entry))))
                       << (p * kPacketSize);
            }
          }
        }
        if (still) {
          ref = e.ref;
          tile_rays = still;
          break;
        }
      }
    }
  }
  for (int p = 0; p < packets; ++p) {
    if (refused >> p & 1) continue;
    for (int i = 0; i < kPacketSize; ++i) hits[p * kPacketSize + i] = Hit{};
  }
  return refused;
}

RAYACCEL_LANE_CODE_END
#endif  // RAYACCEL_AVX_KERNELS

int WideBvh::intersect_tile_from(std::uint32_t start, const BeamFrustum& frustum, const Ray* rays, int count,
                                  Hit* hits, std::uint64_t& ties, bool prove) const {
  if (!has_packet_traversal() || count < 0 || count > kTilePackets * int(detail::kPacketSize) ||
      count % int(detail::kPacketSize) != 0) {
    throw Error("intersect_tile_from: needs the packet traversal and whole packets of 8 rays, at most 8 (got " +
                std::to_string(count) + " rays)");
  }
  ties = 0;
  int refused = (1 << (count / int(detail::kPacketSize))) - 1;
#if RAYACCEL_AVX_KERNELS
  simd::run_with_lanes(isa_, [&]<class Lanes>() RAYACCEL_LANE_LAMBDA {
    if constexpr (Lanes::kWidth == kPacketSize) {
      refused = trace_tile<Lanes>(start, frustum, rays, count, hits, ties, prove);
    }
  });
#else
  (void)start, (void)frustum, (void)rays, (void)hits, (void)prove;
#endif
  return refused;
}

}  // namespace rayaccel::wide
