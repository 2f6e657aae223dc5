// SBVH (Stich, Friedrich, Dietrich 2009): binned object splits plus binned spatial splits with triangle clipping,
// under a reference-growth budget. As in Embree's fast spatial builder (Wald, Woop et al. 2014), the spatial bins are
// costed from the triangle's own edges (no polygon clipping until a split is made), and large subtrees are built in
// parallel, each into a tree of its own that is then spliced into its parent's; two halves built in parallel share
// the budget in proportion to their references, so the tree does not depend on the number of threads.
#include "rayaccel/bvh/sbvh_builder.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "rayaccel/bvh/binned_sah_builder.h"
#include "rayaccel/core/error.h"
#include "rayaccel/geometry/clip_polygon.h"

namespace rayaccel {

namespace {

constexpr std::uint32_t kMaxBins = 64;

struct SpatialSplit {
  int axis = -1;
  float plane = 0.0f;
  float cost = 0.0f;                ///< area(left) * blocks(left) + area(right) * blocks(right)
  std::uint32_t duplicates = 0;     ///< references that would go to both sides
};

/// Nodes of at least this many references build their right subtree on another thread while the left one is built.
constexpr std::size_t kParallelRefs = 2048;

/// Appends `part`, a finished tree, to `tree` as the subtree at `tree.nodes[slot]` (a slot reserved for it).
void splice_subtree(BuildTree& tree, std::uint32_t slot, const BuildTree& part) {
  const auto node_base = static_cast<std::uint32_t>(tree.nodes.size()) - 1;  // part's node i (>= 1) lands here + i
  const auto ref_base = static_cast<std::uint32_t>(tree.refs.size());
  auto relocated = [&](BuildNode n) {
    n.first += n.is_leaf() ? ref_base : node_base;
    return n;
  };
  tree.nodes[slot] = relocated(part.nodes[0]);
  for (std::size_t i = 1; i < part.nodes.size(); ++i) tree.nodes.push_back(relocated(part.nodes[i]));
  tree.refs.insert(tree.refs.end(), part.refs.begin(), part.refs.end());
}

class SbvhBuilder {
 public:
  SbvhBuilder(const Scene& scene, const SbvhOptions& config)
      : scene_(scene), config_(config), block_shift_(__builtin_ctz(config.block_size)),
        spatial_splits_(scene.kind() == PrimitiveKind::triangles) {}

  BuildTree run() {
    PrimRefs refs = scene_.build_references();
    BuildTree tree;
    tree.spatial_splits = spatial_splits_;
    if (refs.empty()) return tree;
    root_area_ = bounds_of(refs).surface_area();
    auto extra = static_cast<std::size_t>(static_cast<double>(refs.size()) *
                                          (std::max(1.0f, config_.max_growth) - 1.0f));
    tree.nodes.resize(1);
    build(tree, 0, refs, extra, 1);
    return tree;
  }

 private:
  static void make_leaf(BuildTree& tree, std::uint32_t node, const PrimRefs& refs) {
    tree.nodes[node] = {static_cast<std::uint32_t>(tree.refs.size()), static_cast<std::uint32_t>(refs.size())};
    tree.refs.insert(tree.refs.end(), refs.begin(), refs.end());
  }

  /// Builds the subtree of `refs` at tree.nodes[node]. `extra` is the budget of references spatial splits may still
  /// add: the subtrees built one after the other share it, first come first served (the paper's global budget);
  /// where two subtrees are built in parallel, each gets a share in proportion to its references and gives back what
  /// it did not spend when both are done, so the tree is the same whatever the number of threads.
  void build(BuildTree& tree, std::uint32_t node, PrimRefs& refs, std::size_t& extra, int depth) const {
    const std::size_t n = refs.size();
    PrimRefs left, right;
    if (n == 1 || depth >= kBvhMedianDepth) {
      if (n <= config_.max_leaf_size) return make_leaf(tree, node, refs);
      median(refs, left, right);
    } else {
      const AABB bounds = bounds_of(refs);
      const BinnedSplit object = find_binned_split(refs, config_.bin_count, block_shift_);
      SpatialSplit spatial;
      const bool overlapping = object.axis < 0 || intersection(object.left, object.right).surface_area() >
                                                      config_.overlap_alpha * root_area_;
      if (spatial_splits_ && overlapping && extra > 0) spatial = find_spatial_split(refs, bounds);
      const bool use_spatial = spatial.axis >= 0 && (object.axis < 0 || spatial.cost < object.cost) &&
                               spatial.duplicates <= extra;
      const float best = use_spatial ? spatial.cost : object.cost;
      if ((object.axis < 0 && !use_spatial) ||
          sah_prefers_leaf(n, bounds.surface_area(), best, config_.max_leaf_size, config_.costs, block_shift_)) {
        if (n <= config_.max_leaf_size) return make_leaf(tree, node, refs);
        median(refs, left, right);
      } else if (!use_spatial || !split_spatially(refs, spatial, extra, left, right)) {
        const std::size_t k = object.axis >= 0 ? partition_binned(refs, object, config_.bin_count) : 0;
        if (k == 0 || k == n) {
          median(refs, left, right);
        } else {
          left.assign(refs.begin(), refs.begin() + static_cast<std::ptrdiff_t>(k));
          right.assign(refs.begin() + static_cast<std::ptrdiff_t>(k), refs.end());
        }
      }
    }
    PrimRefs().swap(refs);  // release before descending: peak memory stays near the final size
    const auto child = static_cast<std::uint32_t>(tree.nodes.size());
    tree.nodes.resize(tree.nodes.size() + 2);
    tree.nodes[node] = {child, 0};
    if (n < kParallelRefs) {
      build(tree, child, left, extra, depth + 1);
      build(tree, child + 1, right, extra, depth + 1);
      return;
    }
    auto left_extra = static_cast<std::size_t>(static_cast<double>(extra) * static_cast<double>(left.size()) /
                                               static_cast<double>(left.size() + right.size()));
    std::size_t right_extra = extra - left_extra;
    BuildTree right_tree;
    right_tree.nodes.resize(1);
    tbb::parallel_invoke([&] { build(tree, child, left, left_extra, depth + 1); },
                         [&] { build(right_tree, 0, right, right_extra, depth + 1); });
    splice_subtree(tree, child + 1, right_tree);
    extra = left_extra + right_extra;
  }

  static void median(PrimRefs& refs, PrimRefs& left, PrimRefs& right) {
    const auto k = static_cast<std::ptrdiff_t>(split_at_median(refs));
    left.assign(refs.begin(), refs.begin() + k);
    right.assign(refs.begin() + k, refs.end());
  }

  /// Bounds of the part of ref's triangle inside ref.bounds restricted to [lo, hi] on axis.
  AABB part_bounds(const PrimRef& ref, int axis, float lo, float hi) const {
    AABB slab = ref.bounds;
    slab.lo[axis] = std::max(slab.lo[axis], lo);
    slab.hi[axis] = std::min(slab.hi[axis], hi);
    if (slab.is_empty()) return AABB::empty();
    const auto& t = scene_.triangle(ref.prim_id);
    return clip_triangle_to_box(t[0], t[1], t[2], slab);
  }

  /// Cost estimate of a spatial split (the split itself clips exactly, in part_bounds): extends box[k], for each
  /// bin k in b0..b1 that the reference spans on `axis`, by the bounds of the triangle's part between plane[k] and
  /// plane[k + 1], cut at the reference's box. The part's corners are the triangle's vertices inside the slab and
  /// the points where its edges cross the slab's planes; with the vertices in order along the axis (a, m, c), every
  /// plane strictly between a and c crosses the edge a-c and one of a-m and m-c. Computed in double, so that the
  /// differences of far-apart float coordinates stay finite.
  void add_slab_parts(const PrimRef& r, int axis, std::uint32_t b0, std::uint32_t b1,
                      const std::array<float, kMaxBins + 1>& plane, std::array<AABB, kMaxBins>& box) const {
    std::array<Vec3, 3> v = scene_.triangle(r.prim_id);
    std::sort(v.begin(), v.end(), [axis](const Vec3& p, const Vec3& q) { return p[axis] < q[axis]; });
    auto point_on = [axis](const Vec3& p, const Vec3& q, double at) {
      const double span = double(q[axis]) - p[axis];
      const double f = span > 0.0 ? std::clamp((at - p[axis]) / span, 0.0, 1.0) : 0.0;
      Vec3 x;
      for (int i = 0; i < 3; ++i) x[i] = static_cast<float>(p[i] + (double(q[i]) - p[i]) * f);
      x[axis] = static_cast<float>(at);
      return x;
    };
    std::array<Vec3, 2> crossing{};  // where the edges cross the slab's lower plane (from the previous bin)
    std::size_t next_vertex = 0;
    for (std::uint32_t k = b0; k <= b1; ++k) {
      AABB part;
      if (k > b0) part.extend(crossing[0]).extend(crossing[1]);
      // Vertices up to the slab's upper plane (all that are left, in the last bin).
      while (next_vertex < 3 && (k == b1 || v[next_vertex][axis] <= plane[k + 1])) part.extend(v[next_vertex++]);
      if (k < b1) {
        const double at = plane[k + 1];
        crossing[0] = point_on(v[0], v[2], at);
        crossing[1] = at <= v[1][axis] ? point_on(v[0], v[1], at) : point_on(v[1], v[2], at);
        part.extend(crossing[0]).extend(crossing[1]);
      }
      const AABB inside = intersection(part, r.bounds);
      if (!inside.is_empty()) box[k].extend(inside);
    }
  }

  SpatialSplit find_spatial_split(const PrimRefs& refs, const AABB& bounds) const {
    SpatialSplit best;
    const std::uint32_t bins = config_.bin_count;
    for (int axis = 0; axis < 3; ++axis) {
      // In double: a box from -FLT_MAX to FLT_MAX has a float extent of infinity, and (x - lo) * bins can overflow
      // float where the bin itself is finite (the fuzz tier found the cast of that infinity).
      const double lo = bounds.lo[axis], extent = double(bounds.hi[axis]) - lo;
      if (!(extent > 0.0) || !std::isfinite(extent)) continue;
      std::array<float, kMaxBins + 1> plane{};
      for (std::uint32_t k = 0; k <= bins; ++k) plane[k] = static_cast<float>(lo + extent * k / bins);
      plane[0] = bounds.lo[axis];
      plane[bins] = bounds.hi[axis];
      auto bin_of = [&](float x) {
        const double k = (double(x) - lo) * bins / extent;  // NaN (from a NaN x) lands in bin 0
        return k >= bins - 1 ? bins - 1 : k > 0.0 ? static_cast<std::uint32_t>(k) : 0u;
      };
      std::array<AABB, kMaxBins> box{};
      std::array<std::uint32_t, kMaxBins> enter{}, exit{};
      for (const PrimRef& r : refs) {
        const std::uint32_t b0 = bin_of(r.bounds.lo[axis]), b1 = bin_of(r.bounds.hi[axis]);
        ++enter[b0];
        ++exit[b1];
        if (b0 == b1) {
          box[b0].extend(r.bounds);
          continue;
        }
        add_slab_parts(r, axis, b0, b1, plane, box);
      }
      std::array<float, kMaxBins> right_cost{};
      std::array<std::uint32_t, kMaxBins> right_count{};
      AABB acc;
      std::uint32_t count = 0;
      for (std::uint32_t k = bins - 1; k > 0; --k) {
        acc.extend(box[k]);
        count += exit[k];
        right_cost[k] = acc.surface_area() * blocks(count);
        right_count[k] = count;
      }
      AABB left;
      std::uint32_t left_count = 0;
      for (std::uint32_t k = 0; k + 1 < bins; ++k) {
        left.extend(box[k]);
        left_count += enter[k];
        if (left_count == 0 || right_count[k + 1] == 0) continue;
        const float cost = left.surface_area() * blocks(left_count) + right_cost[k + 1];
        if (best.axis < 0 || cost < best.cost) {
          best.axis = axis;
          best.plane = plane[k + 1];
          best.cost = cost;
          best.duplicates = left_count + right_count[k + 1] - static_cast<std::uint32_t>(refs.size());
        }
      }
    }
    return best;
  }

  /// Distributes refs by the plane, clipping the ones that cross it. False (nothing changed) when a side would be
  /// empty, which rounding can cause.
  bool split_spatially(const PrimRefs& refs, const SpatialSplit& split, std::size_t& extra, PrimRefs& left,
                       PrimRefs& right) const {
    const int axis = split.axis;
    const float inf = std::numeric_limits<float>::infinity();
    for (const PrimRef& r : refs) {
      if (r.bounds.hi[axis] <= split.plane) {
        left.push_back(r);
      } else if (r.bounds.lo[axis] >= split.plane) {
        right.push_back(r);
      } else {
        const AABB l = part_bounds(r, axis, -inf, split.plane);
        const AABB h = part_bounds(r, axis, split.plane, inf);
        if (!l.is_empty()) left.push_back({l, r.prim_id});
        if (!h.is_empty()) right.push_back({h, r.prim_id});
      }
    }
    if (left.empty() || right.empty() || left.size() + right.size() > refs.size() + extra) {
      left.clear();
      right.clear();
      return false;
    }
    extra -= left.size() + right.size() - refs.size();
    return true;
  }

  /// References counted in started blocks of 2^block_shift_, as the object splits count them.
  float blocks(std::uint32_t count) const {
    return static_cast<float>((count + (1u << block_shift_) - 1) >> block_shift_);
  }

  const Scene& scene_;
  const SbvhOptions& config_;
  int block_shift_ = 0;
  bool spatial_splits_ = false;  ///< triangles: spatial splits are tried; other primitives get object splits only
  float root_area_ = 0.0f;
};

}  // namespace

BuildTree build_sbvh(const Scene& scene, const SbvhOptions& config) {
  if (config.bin_count < 2 || config.bin_count > kMaxBins) {
    throw Error("SBVH: bin count " + std::to_string(config.bin_count) + " is outside 2.." + std::to_string(kMaxBins));
  }
  if (config.block_size == 0 || config.block_size > 64 || (config.block_size & (config.block_size - 1)) != 0) {
    throw Error("SBVH: block size " + std::to_string(config.block_size) + " is not a power of two in 1..64");
  }
  return SbvhBuilder(scene, config).run();
}

}  // namespace rayaccel
