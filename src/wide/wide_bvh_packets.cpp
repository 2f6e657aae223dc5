// Packet traversal of the eight-wide BVH: eight coherent rays traced together (Wald, Slusallek, Benthin, Wagner
// 2001) with the packet-per-child box test of Embree's hybrid traversal (Wald et al. 2014), every lane doing the
// single-ray kernels' float operations for its ray; packets off the fast path are traced ray by ray. Under a query
// context each lane's rules are asked before every triangle test (packet_context.h).
#include <algorithm>
#include <array>
#include <cfloat>
#include <cstddef>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>

#include "packet_context.h"
#include "packet_lanes.h"
#include "rayaccel/core/error.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel::wide {

#if RAYACCEL_AVX_KERNELS
RAYACCEL_LANE_CODE_BEGIN

template <class S, bool AnyHit, class Context, bool kTies>
RAYACCEL_LANE_INLINE int WideBvh::trace_packet(const Ray* packet_rays, int count, Hit* hits, Context& context,
                                               std::uint32_t start) const {
  using F = typename S::F;
  constexpr bool kWithContext = !std::is_same_v<Context, NoPacketContext>;
  static_assert(!(kTies && (AnyHit || kWithContext)), "ties are watched for plain closest hits only");
  const std::uint32_t first_ref = kTies ? start : root_;
  int ties = 0;  // kTies: the lanes a tie or the scalar kernel may have decided (intersect_packet_from())
  std::array<Ray, kPacketSize> padded;  // a last, partial packet: void rays in the missing lanes
  const Ray* rays = packet_rays;
  if (count < kPacketSize) {
    for (int i = 0; i < kPacketSize; ++i) padded[i] = i < count ? packet_rays[i] : void_ray();
    rays = padded.data();
  }
  const PacketLanes<S> lanes_in(rays);
  std::array<Hit, kPacketSize> hit;
  for (int i = 0; i < kPacketSize; ++i) hit[i].t = lanes_in.far[i];
  NoStats none;
  if (lanes_in.active && !lanes_in.fast) {
    // Rays starting behind their origin, subnormal origin coordinates or rays of different axes (rare in coherent
    // packets): ray by ray, with the single-ray traversal.
    const std::array<PreparedRay, kPacketSize> prepared = prepare_rays(rays, std::make_index_sequence<8>{});
    for (int i = 0; i < kPacketSize; ++i) {
      if (!(lanes_in.active >> i & 1)) continue;
      if constexpr (kWithContext) {
        traverse<simd::BoxKernel<S>, AnyHit>(nodes8_, root_, prepared[i], hit[i], context.lane(i));
      } else {
        traverse<simd::BoxKernel<S>, AnyHit>(nodes8_, first_ref, prepared[i], hit[i], none);
      }
    }
  } else if (lanes_in.active) {
    // With the same direction signs in every active ray (coherent packets almost always), each axis's near plane is
    // the same in every lane and is read directly; otherwise each lane selects its own.
    int near_offset[3];
    bool same_signs = true;
    for (int a = 0; a < 3; ++a) {
      const int negative = S::movemask(lanes_in.direction[a]) & lanes_in.active;  // sign bits, -0 included
      same_signs &= negative == 0 || negative == lanes_in.active;
      near_offset[a] = negative ? 1 : 0;
    }
    const auto trace = [&]<bool kSameSigns>() RAYACCEL_LANE_LAMBDA {
      const F* near_is_hi = lanes_in.direction;  // the sign bit of d selects the near plane, as PreparedRay::negative
      const F t_min = lanes_in.t_min;
      F far_bound = S::load(lanes_in.far);

      // Child c of `node` against the rays of `lane_mask` (within far_bound): returns the rays that meet its box, in
      // `meets` as lanes too, and each lane's entry distance in t_near.
      const auto meet_child = [&](const Node<kPacketSize>& node, int c, const F& lane_mask, F& t_near, F& meets)
                                  RAYACCEL_LANE_LAMBDA {
        F near_plane[3], far_plane[3];
        for (int a = 0; a < 3; ++a) {
          if constexpr (kSameSigns) {
            near_plane[a] = S::broadcast(&node.bounds[a][near_offset[a]][c]);
            far_plane[a] = S::broadcast(&node.bounds[a][1 - near_offset[a]][c]);
          } else {
            const F lo = S::broadcast(&node.bounds[a][0][c]);
            const F hi = S::broadcast(&node.bounds[a][1][c]);
            near_plane[a] = S::blend(lo, hi, near_is_hi[a]);
            far_plane[a] = S::blend(hi, lo, near_is_hi[a]);
          }
        }
        slab_meets<S>(lanes_in, near_plane, far_plane, far_bound, t_near, meets);
        meets = S::bit_and(meets, lane_mask);
        return S::movemask(meets);
      };
      // Triangle j of `block` against the rays of `testing`; returns the rays whose hit changed. Under a context with a
      // filter, each new hit is kept only when the filter accepts it (a rejected lane gets its hit and far bound back).
      const auto test_triangle = [&](const simd::Triangle4& block, int j, int testing) RAYACCEL_LANE_LAMBDA {
        if constexpr (kWithContext) {
          if (context.has_filter()) {
            const std::array<Hit, kPacketSize> before = hit;
            const int changed = intersect_triangle_rays<S>(lanes_in.triangle, rays, testing, lanes_in.axes, block, j,
                                                           hit.data(), far_bound);
            const int rejected = changed ? context.reject(changed, hit.data(), before.data()) : 0;
            if (rejected) simd::set_lanes_to_hits<S>(far_bound, rejected, hit.data());
            return changed & ~rejected;
          }
        }
        return intersect_triangle_rays<S, kTies>(lanes_in.triangle, rays, testing, lanes_in.axes, block, j,
                                                 hit.data(), far_bound, &ties);
      };
      // Every triangle of leaf `ref` against the rays of `leaf_rays`; returns the rays whose hit changed. Any-hit
      // drops a ray from the remaining triangles at its first hit and stops when every ray of the leaf has one.
      const auto test_leaf = [&](std::uint32_t ref, int leaf_rays) RAYACCEL_LANE_LAMBDA {
        int found = 0;
        const std::uint32_t end = leaf_first_block(ref) + leaf_block_count(ref);
        for (std::uint32_t b = leaf_first_block(ref); b < end; ++b) {
          const simd::Triangle4& block = blocks_[b];
          for (int j = 0; j < 4 && block.prim_id[j] != kInvalidPrimId; ++j) {  // padding only at the end
            int testing = AnyHit ? leaf_rays & ~found : leaf_rays;
            if constexpr (kWithContext) {
              testing = context.allowed(block.prim_id[j], testing);  // the lanes whose rules let them test it
              if (!testing) continue;
            }
            found |= test_triangle(block, j, testing);
            if (AnyHit && found == leaf_rays) return found;
          }
        }
        return found;
      };

      if constexpr (AnyHit) {
        // Any hit: a ray's far bound stays Hit::begin's until its first hit, when it leaves the packet (`live`), so
        // nothing on the stack is culled by distance: entries hold the rays that met the subtree's box, and the
        // children met are taken in lane order (the first entered, the others pushed); the single-ray any-hit traversal
        // takes them in the node's order for its octant, which the rays of a packet need not share.
        struct Entry {
          std::uint32_t ref;
          int lanes;
        };
        Entry stack[kStackSize];
        int top = 0;
        int live = lanes_in.active;
        std::uint32_t ref = root_;
        int lanes = live;
        for (;;) {
          if (ref & kLeafBit) {
            live &= ~test_leaf(ref, lanes);
            if (!live) return;
          } else {
            const Node<kPacketSize>& node = nodes8_[ref];
            const F lane_mask = S::lanes_from_bits(lanes);
            int next_lanes = 0;
            std::uint32_t next = 0;
            for (int c = 0; c < kPacketSize && node.child[c] != kEmptyChild; ++c) {
              F t_near, meets;
              const int bits = meet_child(node, c, lane_mask, t_near, meets);
              if (!bits) continue;
              if (next_lanes) {
                stack[top++] = {node.child[c], bits};
              } else {
                next = node.child[c];
                next_lanes = bits;
              }
            }
            if (next_lanes) {
              ref = next;
              lanes = next_lanes;
              continue;
            }
          }
          // Pop the next subtree that some ray still in the packet met.
          for (;;) {
            if (top == 0) return;
            const Entry& e = stack[--top];
            if (e.lanes & live) {
              ref = e.ref;
              lanes = e.lanes & live;
              break;
            }
          }
        }
      } else {
        struct alignas(32) Entry {
          float t_entry[kPacketSize];  ///< each ray's entry distance into the subtree (meaningful in `lanes` only)
          std::uint32_t ref;
          int lanes;  ///< the rays that met the subtree's box
        };
        Entry stack[kStackSize];
        int top = 0;
        std::uint32_t ref = first_ref;
        int lanes = lanes_in.active;
        F entry = t_min;
        for (;;) {
          if (ref & kLeafBit) {
            // The rays that met the leaf's box and have not hit anything nearer.
            const int leaf_rays = lanes & S::movemask(S::le(entry, far_bound));
            if (leaf_rays) test_leaf(ref, leaf_rays);
          } else {
            const Node<kPacketSize>& node = nodes8_[ref];
            const F lane_mask = S::lanes_from_bits(lanes);
            // The children met, in order of their nearest entry.
            alignas(32) float child_entry[kPacketSize][kPacketSize];
            float nearest[kPacketSize];
            int child_lanes[kPacketSize];
            int met[kPacketSize];
            int met_count = 0;
            for (int c = 0; c < kPacketSize && node.child[c] != kEmptyChild; ++c) {
              F t_near, meets;
              const int bits = meet_child(node, c, lane_mask, t_near, meets);
              if (!bits) continue;
              S::store(child_entry[c], t_near);
              const float d =
                  S::horizontal_min(S::blend(S::set1(std::numeric_limits<float>::infinity()), t_near, meets));
              // Insertion by nearest entry, farthest first, so the nearest is taken from the end.
              int k = met_count++;
              for (; k > 0 && nearest[met[k - 1]] < d; --k) met[k] = met[k - 1];
              met[k] = c;
              nearest[c] = d;
              child_lanes[c] = bits;
            }
            if (met_count > 0) {
              for (int k = 0; k < met_count - 1; ++k) {
                const int c = met[k];
                Entry& e = stack[top++];
                S::store(e.t_entry, S::load(child_entry[c]));
                e.ref = node.child[c];
                e.lanes = child_lanes[c];
              }
              const int c = met[met_count - 1];
              ref = node.child[c];
              lanes = child_lanes[c];
              entry = S::load(child_entry[c]);
              continue;
            }
          }
          // Pop the next subtree that some ray still needs: entered before that ray's closest hit.
          for (;;) {
            if (top == 0) return;
            const Entry& e = stack[--top];
            const F e_entry = S::load(e.t_entry);
            const int still = e.lanes & S::movemask(S::le(e_entry, far_bound));
            if (still) {
              ref = e.ref;
              lanes = still;
              entry = e_entry;
              break;
            }
          }
        }
      }
    };
    if (same_signs) {
      trace.template operator()<true>();
    } else {
      trace.template operator()<false>();
    }
  }
  // Each record written whole (Hit::finish() on a copy would store fields and then reload the record, a store
  // forwarding stall per ray); a miss is Hit{}, which is what finish() makes of it.
  for (int i = 0; i < count; ++i) hits[i] = hit[i].found() ? hit[i] : Hit{};
  return ties & ((1 << count) - 1);
}

RAYACCEL_LANE_CODE_END
#endif  // RAYACCEL_AVX_KERNELS

namespace {

/// Runs packet(first, count) for every packet of a batch of `rays` (count <= 8 rays from rays[first]), in parallel
/// chunks of whole packets, with the eight-lane kernels of `isa` (avx2 or avx512: eight-wide nodes) as template
/// argument.
template <class Packet>
void for_each_packet(std::span<const Ray> rays, simd::Isa isa, const Packet& packet) {
#if RAYACCEL_AVX_KERNELS
  detail::parallel_for_packets(rays.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t first = begin; first < end; first += detail::kPacketSize) {
      const int count = static_cast<int>(std::min(detail::kPacketSize, end - first));
      simd::run_with_lanes(isa, [&]<class Lanes>() RAYACCEL_LANE_LAMBDA {
        if constexpr (Lanes::kWidth == kPacketSize) packet.template operator()<Lanes>(first, count);
      });
    }
  });
#else
  (void)rays, (void)isa, (void)packet;
#endif
}

}  // namespace

bool WideBvh::has_packet_traversal() const {
  // Eight-wide nodes exist only in builds with the eight-lane kernels (simd/isa.h).
  return RAYACCEL_AVX_KERNELS && width_ == 8 && triangles_ && root_ != kEmptyChild;
}

void WideBvh::intersect_packets(std::span<const Ray> rays, std::span<Hit> hits) const {
  if (!has_packet_traversal()) {
    intersect(rays, hits);  // no packet traversal for four-wide nodes or other primitives: one by one
    return;
  }
  detail::check_batch_sizes(rays.size(), hits.size(), 0);
  for_each_packet(rays, isa_, [&]<class Lanes>(std::size_t first, int count) RAYACCEL_LANE_LAMBDA {
    NoPacketContext none;
    trace_packet<Lanes, false>(rays.data() + first, count, hits.data() + first, none);
  });
}

void WideBvh::occluded_packets(std::span<const Ray> rays, std::span<std::uint8_t> occluded_out) const {
  if (!has_packet_traversal()) {
    occluded(rays, occluded_out);  // one by one, as intersect_packets()
    return;
  }
  detail::check_batch_sizes(rays.size(), occluded_out.size(), 0);
  for_each_packet(rays, isa_, [&]<class Lanes>(std::size_t first, int count) RAYACCEL_LANE_LAMBDA {
    std::array<Hit, detail::kPacketSize> hits;
    NoPacketContext none;
    trace_packet<Lanes, true>(rays.data() + first, count, hits.data(), none);
    for (int i = 0; i < count; ++i) occluded_out[first + i] = hits[i].found() ? 1 : 0;
  });
}

void WideBvh::intersect_packets(const QueryContext& context, std::span<const Ray> rays, std::span<Hit> hits) const {
  if (!has_packet_traversal()) {
    intersect(context, rays, hits);  // one by one, as intersect_packets()
    return;
  }
  detail::check_batch_sizes(rays.size(), hits.size(), 0);
  detail::check_context_sizes(context, rays.size());
  for_each_packet(rays, isa_, [&]<class Lanes>(std::size_t first, int count) RAYACCEL_LANE_LAMBDA {
    PacketContext<static_cast<int>(detail::kPacketSize)> lanes(context, first, count);
    trace_packet<Lanes, false>(rays.data() + first, count, hits.data() + first, lanes);
  });
}

int WideBvh::intersect_packet_from(std::uint32_t start, const Ray* rays, int count, Hit* hits) const {
  if (!has_packet_traversal() || count < 0 || count > int(detail::kPacketSize)) {
    throw Error("intersect_packet_from: needs the packet traversal and at most 8 rays (got " + std::to_string(count) +
                ")");
  }
  int ties = 0;
#if RAYACCEL_AVX_KERNELS
  simd::run_with_lanes(isa_, [&]<class Lanes>() RAYACCEL_LANE_LAMBDA {
    if constexpr (Lanes::kWidth == kPacketSize) {
      NoPacketContext none;
      ties = trace_packet<Lanes, false, NoPacketContext, true>(rays, count, hits, none, start);
    }
  });
#else
  (void)start, (void)rays, (void)hits;
#endif
  return ties;
}

void WideBvh::occluded_packets(const QueryContext& context, std::span<const Ray> rays,
                               std::span<std::uint8_t> occluded_out) const {
  if (!has_packet_traversal()) {
    occluded(context, rays, occluded_out);  // one by one, as intersect_packets()
    return;
  }
  detail::check_batch_sizes(rays.size(), occluded_out.size(), 0);
  detail::check_context_sizes(context, rays.size());
  for_each_packet(rays, isa_, [&]<class Lanes>(std::size_t first, int count) RAYACCEL_LANE_LAMBDA {
    std::array<Hit, detail::kPacketSize> hits;
    PacketContext<static_cast<int>(detail::kPacketSize)> lanes(context, first, count);
    trace_packet<Lanes, true>(rays.data() + first, count, hits.data(), lanes);
    for (int i = 0; i < count; ++i) occluded_out[first + i] = hits[i].found() ? 1 : 0;
  });
}

}  // namespace rayaccel::wide
