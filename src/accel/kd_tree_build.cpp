// kd-tree builders: the median split (axes cycling) and the O(N log N) SAH build of Wald & Havran 2006 (sorted event
// lists split and merged on the way down, perfect splits); K_I per started block of block_size references.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "rayaccel/accel/kd_tree.h"
#include "rayaccel/core/error.h"

namespace rayaccel {

int kd_tree_max_depth(const KdTreeOptions& options, std::size_t n) {
  return split_tree_depth_limit(options.max_depth, n);
}

namespace {

/// Appends a node placeholder and returns its index.
std::uint32_t reserve_node(KdTreeData& out) {
  if (out.nodes.size() > KdNode::kMaxField) throw Error("kd-tree: more nodes than the 30-bit child index holds");
  out.nodes.emplace_back();
  return static_cast<std::uint32_t>(out.nodes.size() - 1);
}

void make_leaf(KdTreeData& out, std::uint32_t node, const std::vector<std::uint32_t>& prims) {
  if (prims.size() > KdNode::kMaxField) throw Error("kd-tree: a leaf holds more references than 30 bits count");
  out.nodes[node] = KdNode::leaf(static_cast<std::uint32_t>(out.prim_indices.size()),
                                 static_cast<std::uint32_t>(prims.size()));
  out.prim_indices.insert(out.prim_indices.end(), prims.begin(), prims.end());
}

AABB child_cell(const AABB& cell, int axis, float split, bool above) {
  AABB c = cell;
  (above ? c.lo : c.hi)[axis] = split;
  return c;
}

// ---- median build ----------------------------------------------------------------------------------------------

class MedianBuilder {
 public:
  MedianBuilder(const KdTreeOptions& options, const ClipToCell& clip, int max_depth)
      : options_(options), clip_(clip), max_depth_(max_depth) {}

  void build(KdTreeData& out, PrimRefs refs, const AABB& cell, int depth) {
    const std::uint32_t node = reserve_node(out);
    const int axis = depth % 3;
    const std::size_t n = refs.size();
    float split = 0.0f;
    bool can_split = n > static_cast<std::size_t>(options_.leaf_size) && depth < max_depth_;
    if (can_split) {
      std::vector<float> centroids(n);
      for (std::size_t i = 0; i < n; ++i) centroids[i] = refs[i].bounds.center()[axis];
      std::nth_element(centroids.begin(), centroids.begin() + n / 2, centroids.end());
      split = centroids[n / 2];
      can_split = split > cell.lo[axis] && split < cell.hi[axis];
    }
    PrimRefs below, above;
    if (can_split) {
      for (const PrimRef& r : refs) {
        if (r.bounds.lo[axis] <= split) add_clipped(below, r.prim_id, child_cell(cell, axis, split, false));
        if (r.bounds.hi[axis] >= split) add_clipped(above, r.prim_id, child_cell(cell, axis, split, true));
      }
      // Stop where a side does not shrink: below that, straddling references would only be copied again.
      can_split = below.size() < n && above.size() < n;
    }
    if (!can_split) {
      std::vector<std::uint32_t> prims(n);
      for (std::size_t i = 0; i < n; ++i) prims[i] = refs[i].prim_id;
      make_leaf(out, node, prims);
      return;
    }
    refs = {};
    build(out, std::move(below), child_cell(cell, axis, split, false), depth + 1);
    const std::uint32_t above_node = static_cast<std::uint32_t>(out.nodes.size());
    out.nodes[node] = KdNode::interior(axis, split, above_node);
    build(out, std::move(above), child_cell(cell, axis, split, true), depth + 1);
  }

 private:
  void add_clipped(PrimRefs& side, std::uint32_t prim, const AABB& cell) const {
    const AABB b = clip_(prim, cell);
    if (!b.is_empty()) side.push_back({b, prim});
  }

  const KdTreeOptions& options_;
  const ClipToCell& clip_;
  int max_depth_;
};

// ---- SAH build (Wald & Havran 2006) ----------------------------------------------------------------------------

enum EventType : std::uint8_t { kEnd = 0, kPlanar = 1, kStart = 2 };

/// One end of a reference's clipped bounds on one axis. Sorted by (axis, position, type): at equal positions ends
/// come before planar events before starts, as the sweep requires.
struct Event {
  float position;      // 4 bytes
  std::uint32_t prim;  // 4 bytes
  std::uint8_t axis;   // 1 byte
  std::uint8_t type;   // 1 byte (EventType)
};

bool event_less(const Event& a, const Event& b) {
  if (a.axis != b.axis) return a.axis < b.axis;
  if (a.position != b.position) return a.position < b.position;
  return a.type < b.type;
}

void add_events(std::vector<Event>& events, std::uint32_t prim, const AABB& b) {
  for (std::uint8_t axis = 0; axis < 3; ++axis) {
    if (b.lo[axis] == b.hi[axis]) {
      events.push_back({b.lo[axis], prim, axis, kPlanar});
    } else {
      events.push_back({b.lo[axis], prim, axis, kStart});
      events.push_back({b.hi[axis], prim, axis, kEnd});
    }
  }
}

struct SplitChoice {
  double cost = std::numeric_limits<double>::infinity();
  int axis = -1;
  float position = 0.0f;
  bool planar_below = true;  ///< references lying in the split plane go below (else above)
};

enum Side : std::uint8_t { kBoth = 0, kBelowOnly = 1, kAboveOnly = 2 };

class SahBuilder {
 public:
  SahBuilder(const KdTreeOptions& options, const ClipToCell& clip, int max_depth, std::uint32_t max_prim_id)
      : options_(options), clip_(clip), max_depth_(max_depth), side_(std::size_t(max_prim_id) + 1, kBoth) {}

  void build(KdTreeData& out, std::vector<Event> events, std::size_t n, const AABB& cell, int depth) {
    const std::uint32_t node = reserve_node(out);
    const SplitChoice choice = find_split(events, n, cell);
    const double leaf_cost = kd_leaf_cost(options_, n);
    if (depth >= max_depth_ || n == 0 || choice.axis < 0 || !(choice.cost < leaf_cost)) {
      std::vector<std::uint32_t> prims;
      prims.reserve(n);
      for (const Event& e : events) {
        if (e.axis == 0 && e.type != kEnd) prims.push_back(e.prim);
      }
      make_leaf(out, node, prims);
      return;
    }
    const AABB below_cell = child_cell(cell, choice.axis, choice.position, false);
    const AABB above_cell = child_cell(cell, choice.axis, choice.position, true);
    std::vector<Event> below, above;
    std::size_t n_below = 0, n_above = 0;
    split_events(events, choice, below_cell, above_cell, below, above, n_below, n_above);
    events = {};
    build(out, std::move(below), n_below, below_cell, depth + 1);
    const std::uint32_t above_node = static_cast<std::uint32_t>(out.nodes.size());
    out.nodes[node] = KdNode::interior(choice.axis, choice.position, above_node);
    build(out, std::move(above), n_above, above_cell, depth + 1);
  }

 private:
  /// SAH cost of splitting `cell` at `position` on `axis` with the given counts, planar references on the cheaper
  /// side. Candidates on the cell boundary are rejected (they would make no progress).
  void evaluate(const AABB& cell, double inv_area, int axis, float position, std::size_t n_below,
                std::size_t n_above, std::size_t n_planar, SplitChoice& best) const {
    if (!(position > cell.lo[axis] && position < cell.hi[axis])) return;
    const double p_below = child_cell(cell, axis, position, false).surface_area() * inv_area;
    const double p_above = child_cell(cell, axis, position, true).surface_area() * inv_area;
    auto cost = [&](std::size_t nb, std::size_t na) {
      const double bonus = (nb == 0 || na == 0) ? 1.0 - options_.empty_bonus : 1.0;
      return bonus *
             (options_.traversal_cost + p_below * kd_leaf_cost(options_, nb) + p_above * kd_leaf_cost(options_, na));
    };
    const double planar_below = cost(n_below + n_planar, n_above);
    const double planar_above = cost(n_below, n_above + n_planar);
    const bool below_wins = planar_below <= planar_above;
    const double c = below_wins ? planar_below : planar_above;
    if (c < best.cost) best = {c, axis, position, below_wins};
  }

  /// The sweep of Wald & Havran (section 4.3): one pass over the sorted events tracks, per axis, how many
  /// references lie entirely below, in, and above each candidate plane.
  SplitChoice find_split(const std::vector<Event>& events, std::size_t n, const AABB& cell) const {
    SplitChoice best;
    const double area = cell.surface_area();
    if (!(area > 0.0) || n == 0) return best;
    const double inv_area = 1.0 / area;
    std::size_t n_below[3] = {0, 0, 0}, n_above[3] = {n, n, n};
    const std::size_t m = events.size();
    for (std::size_t i = 0; i < m;) {
      const int axis = events[i].axis;
      const float p = events[i].position;
      std::size_t ends = 0, planars = 0, starts = 0;
      auto same = [&](std::size_t j, std::uint8_t type) {
        return j < m && events[j].axis == axis && events[j].position == p && events[j].type == type;
      };
      while (same(i, kEnd)) { ++ends; ++i; }
      while (same(i, kPlanar)) { ++planars; ++i; }
      while (same(i, kStart)) { ++starts; ++i; }
      n_above[axis] -= planars + ends;
      evaluate(cell, inv_area, axis, p, n_below[axis], n_above[axis], planars, best);
      n_below[axis] += starts + planars;
    }
    return best;
  }

  /// Classifies references against the chosen plane, keeps the events of one-sided references in order, clips the
  /// straddling ones to each child cell for new events, and merges the two sorted runs per child (section 4.4).
  void split_events(const std::vector<Event>& events, const SplitChoice& s, const AABB& below_cell,
                    const AABB& above_cell, std::vector<Event>& below, std::vector<Event>& above,
                    std::size_t& n_below, std::size_t& n_above) {
    std::vector<std::uint32_t> prims;
    for (const Event& e : events) {
      if (e.axis == 0 && e.type != kEnd) {
        side_[e.prim] = kBoth;
        prims.push_back(e.prim);
      }
    }
    for (const Event& e : events) {
      if (e.axis != s.axis) continue;
      if (e.type == kEnd && e.position <= s.position) side_[e.prim] = kBelowOnly;
      if (e.type == kStart && e.position >= s.position) side_[e.prim] = kAboveOnly;
      if (e.type == kPlanar) {
        if (e.position < s.position || (e.position == s.position && s.planar_below)) side_[e.prim] = kBelowOnly;
        if (e.position > s.position || (e.position == s.position && !s.planar_below)) side_[e.prim] = kAboveOnly;
      }
    }
    std::vector<Event> below_only, above_only, below_new, above_new;
    for (const Event& e : events) {
      if (side_[e.prim] == kBelowOnly) below_only.push_back(e);
      if (side_[e.prim] == kAboveOnly) above_only.push_back(e);
    }
    n_below = n_above = 0;
    for (std::uint32_t prim : prims) {
      if (side_[prim] == kBelowOnly) ++n_below;
      if (side_[prim] == kAboveOnly) ++n_above;
      if (side_[prim] != kBoth) continue;
      const AABB b = clip_(prim, below_cell);
      if (!b.is_empty()) { add_events(below_new, prim, b); ++n_below; }
      const AABB a = clip_(prim, above_cell);
      if (!a.is_empty()) { add_events(above_new, prim, a); ++n_above; }
    }
    std::sort(below_new.begin(), below_new.end(), event_less);
    std::sort(above_new.begin(), above_new.end(), event_less);
    below.resize(below_only.size() + below_new.size());
    std::merge(below_only.begin(), below_only.end(), below_new.begin(), below_new.end(), below.begin(), event_less);
    above.resize(above_only.size() + above_new.size());
    std::merge(above_only.begin(), above_only.end(), above_new.begin(), above_new.end(), above.begin(), event_less);
  }

  const KdTreeOptions& options_;
  const ClipToCell& clip_;
  int max_depth_;
  std::vector<std::uint8_t> side_;  ///< per primitive id: its Side for the split being made
};

AABB root_cell(std::span<const PrimRef> refs) {
  AABB cell;
  for (const PrimRef& r : refs) cell.extend(r.bounds);
  return cell;
}

}  // namespace

KdTreeData build_kd_tree_median(std::span<const PrimRef> refs, const KdTreeOptions& options, const ClipToCell& clip) {
  KdTreeData out;
  out.bounds = root_cell(refs);
  if (refs.empty()) return out;
  MedianBuilder builder(options, clip, kd_tree_max_depth(options, refs.size()));
  builder.build(out, PrimRefs(refs.begin(), refs.end()), out.bounds, 0);
  return out;
}

KdTreeData build_kd_tree_sah(std::span<const PrimRef> refs, const KdTreeOptions& options, const ClipToCell& clip) {
  KdTreeData out;
  out.bounds = root_cell(refs);
  if (refs.empty()) return out;
  std::vector<Event> events;
  events.reserve(refs.size() * 6);
  std::uint32_t max_id = 0;
  for (const PrimRef& r : refs) {
    add_events(events, r.prim_id, r.bounds);
    max_id = std::max(max_id, r.prim_id);
  }
  std::sort(events.begin(), events.end(), event_less);
  SahBuilder builder(options, clip, kd_tree_max_depth(options, refs.size()), max_id);
  builder.build(out, std::move(events), refs.size(), out.bounds, 0);
  return out;
}

}  // namespace rayaccel
