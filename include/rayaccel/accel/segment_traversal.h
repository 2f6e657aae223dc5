// Front-to-back traversal of a binary space partition by ray segments, shared by the kd-tree and the general BSP
// tree (recursive ray traversal of Jansen 1986 / Havran 2000, made robust as in pbrt's kd-tree): each node splits
// the segment [t0, t1] at t_split, the near child is visited first and the far child is kept on a small stack.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "rayaccel/accel/ray_mailbox.h"
#include "rayaccel/core/hit.h"
#include "rayaccel/simd/lane_set.h"

namespace rayaccel {

/// A node still to visit and the part [t0, t1] of the ray that lies in its cell (widened for rounding).
struct SegmentEntry {
  std::uint32_t node;
  float t0, t1;
};

/// The children of a split node that the segment reaches, in visiting order.
struct ChildSegments {
  SegmentEntry child[2];
  int count = 0;
};

/// Splits [t0, t1] between the two children of a node whose plane separates `below` (signed distance < 0) from
/// `above` (signed distance > 0).
///   origin_side: sign of the origin's signed distance (-1, 0, +1).
///   rate: the direction's rate of change of the signed distance; 0 means the ray is parallel to the plane.
///   [ts_lo, ts_hi]: an interval sure to hold the exact crossing distance (ignored when rate == 0).
/// A parallel ray visits only its origin's side, or both sides over the whole segment when its origin lies on the
/// plane. Otherwise the near child (below when rate > 0) gets [t0, min(t1, ts_hi)] and the far child
/// [max(t0, ts_lo), t1], each only when not empty; the two overlap around the plane, so a hit on the plane itself
/// is seen from both.
inline ChildSegments split_segment(std::uint32_t below, std::uint32_t above, int origin_side, float rate, float ts_lo,
                                   float ts_hi, float t0, float t1) {
  ChildSegments out;
  if (rate == 0.0f) {
    if (origin_side <= 0) out.child[out.count++] = {below, t0, t1};
    if (origin_side >= 0) out.child[out.count++] = {above, t0, t1};
    return out;
  }
  const std::uint32_t near_node = rate > 0.0f ? below : above;
  const std::uint32_t far_node = rate > 0.0f ? above : below;
  // Written as negated comparisons so that a NaN split distance visits both children over the whole segment.
  if (!(ts_hi < t0)) out.child[out.count++] = {near_node, t0, ts_hi < t1 ? ts_hi : t1};
  if (!(ts_lo > t1)) out.child[out.count++] = {far_node, ts_lo > t0 ? ts_lo : t0, t1};
  return out;
}

/// Maximum tree depth a segment traversal supports (the stack holds one entry per level).
inline constexpr int kMaxSegmentDepth = 64;
/// Deepest tree the kd-tree and BSP builders make.
inline constexpr int kMaxSplitTreeDepth = kMaxSegmentDepth - 4;

/// The depth limit of a split-plane tree over n primitives: `requested` when > 0, else pbrt's round(8 + 1.3 log2 n);
/// at most kMaxSplitTreeDepth.
inline int split_tree_depth_limit(int requested, std::size_t n) {
  const int automatic = static_cast<int>(std::lround(8.0 + 1.3 * std::log2(double(n > 1 ? n : 1))));
  return std::min(requested > 0 ? requested : automatic, kMaxSplitTreeDepth);
}

/// Result of visiting one node in traverse_segments().
enum class SegmentVisit { descend, leaf_done, stop };

/// Visits the tree from `root` over [t0, t1] front to back. visit(entry, children) handles one node: an interior
/// node fills `children` and returns descend; a leaf tests its primitives and returns leaf_done, or stop to end
/// the traversal (any-hit). Entries whose segment starts at or beyond hit.t are skipped: nothing in them can be
/// closer than the hit already found. Trees must be at most kMaxSegmentDepth deep.
template <class Visit>
RAYACCEL_LANE_INLINE void traverse_segments(std::uint32_t root, float t0, float t1, const Hit& hit, Visit&& visit) {
  SegmentEntry stack[kMaxSegmentDepth];
  int size = 0;
  SegmentEntry current{root, t0, t1};
  for (;;) {
    if (current.t0 < hit.t) {
      ChildSegments children;
      const SegmentVisit result = visit(current, children);
      if (result == SegmentVisit::stop) return;
      if (result == SegmentVisit::descend && children.count > 0) {
        if (children.count == 2) stack[size++] = children.child[1];
        current = children.child[0];
        continue;
      }
    }
    if (size == 0) return;
    current = stack[--size];
  }
}

}  // namespace rayaccel
