// SBVH (Stich, Friedrich, Dietrich 2009): binned object splits plus binned spatial splits with triangle clipping,
// under a reference-growth budget.
#include "rayaccel/bvh/sbvh_builder.h"

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
constexpr std::size_t kClippedPolygonRoom = std::tuple_size_v<ClippedPolygon>;

struct SpatialSplit {
  int axis = -1;
  float plane = 0.0f;
  float cost = 0.0f;                ///< area(left) * blocks(left) + area(right) * blocks(right)
  std::uint32_t duplicates = 0;     ///< references that would go to both sides
};

class SbvhBuilder {
 public:
  SbvhBuilder(const Scene& scene, const SbvhOptions& config)
      : scene_(scene), config_(config), block_shift_(__builtin_ctz(config.block_size)) {}

  BuildTree run() {
    PrimRefs refs = scene_.build_references();
    tree_.spatial_splits = scene_.kind() == PrimitiveKind::triangles;
    if (refs.empty()) return std::move(tree_);
    root_area_ = bounds_of(refs).surface_area();
    budget_ = static_cast<std::size_t>(static_cast<double>(refs.size()) * std::max(1.0f, config_.max_growth));
    live_ = refs.size();
    tree_.nodes.resize(1);
    build(0, refs, 1);
    return std::move(tree_);
  }

 private:
  void make_leaf(std::uint32_t node, const PrimRefs& refs) {
    tree_.nodes[node] = {static_cast<std::uint32_t>(tree_.refs.size()), static_cast<std::uint32_t>(refs.size())};
    tree_.refs.insert(tree_.refs.end(), refs.begin(), refs.end());
  }

  void build(std::uint32_t node, PrimRefs& refs, int depth) {
    const std::size_t n = refs.size();
    PrimRefs left, right;
    if (n == 1 || depth >= kBvhMedianDepth) {
      if (n <= config_.max_leaf_size) return make_leaf(node, refs);
      median(refs, left, right);
    } else {
      const AABB bounds = bounds_of(refs);
      const BinnedSplit object = find_binned_split(refs, config_.bin_count, block_shift_);
      SpatialSplit spatial;
      const bool overlapping = object.axis < 0 || intersection(object.left, object.right).surface_area() >
                                                      config_.overlap_alpha * root_area_;
      if (tree_.spatial_splits && overlapping && live_ < budget_) spatial = find_spatial_split(refs, bounds);
      const bool use_spatial = spatial.axis >= 0 && (object.axis < 0 || spatial.cost < object.cost) &&
                               live_ + spatial.duplicates <= budget_;
      const float best = use_spatial ? spatial.cost : object.cost;
      if ((object.axis < 0 && !use_spatial) ||
          sah_prefers_leaf(n, bounds.surface_area(), best, config_.max_leaf_size, config_.costs, block_shift_)) {
        if (n <= config_.max_leaf_size) return make_leaf(node, refs);
        median(refs, left, right);
      } else if (!use_spatial || !split_spatially(refs, spatial, left, right)) {
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
    const auto child = static_cast<std::uint32_t>(tree_.nodes.size());
    tree_.nodes.resize(tree_.nodes.size() + 2);
    tree_.nodes[node] = {child, 0};
    build(child, left, depth + 1);
    build(child + 1, right, depth + 1);
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
        // Cost estimate only (the partition clips exactly): clip the triangle to the reference once, then the
        // polygon to each bin's slab.
        ClippedPolygon poly;
        std::array<Vec3, kClippedPolygonRoom + 2> slab, part;  // each clip adds at most one vertex
        const int n = clip_triangle_polygon(scene_.triangle(r.prim_id), r.bounds, poly);
        for (std::uint32_t k = b0; k <= b1; ++k) {
          int m = clip_polygon_to_axis_plane(poly.data(), n, axis, plane[k], false, slab.data());
          m = m > 0 ? clip_polygon_to_axis_plane(slab.data(), m, axis, plane[k + 1], true, part.data()) : 0;
          AABB b;
          for (int v = 0; v < m; ++v) b.extend(part[v]);
          box[k].extend(intersection(b, r.bounds));
        }
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
  bool split_spatially(const PrimRefs& refs, const SpatialSplit& split, PrimRefs& left,
                       PrimRefs& right) {
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
    if (left.empty() || right.empty() || left.size() + right.size() > refs.size() + (budget_ - live_)) {
      left.clear();
      right.clear();
      return false;
    }
    live_ += left.size() + right.size() - refs.size();
    return true;
  }

  /// References counted in started blocks of 2^block_shift_, as the object splits count them.
  float blocks(std::uint32_t count) const {
    return static_cast<float>((count + (1u << block_shift_) - 1) >> block_shift_);
  }

  const Scene& scene_;
  const SbvhOptions& config_;
  int block_shift_ = 0;
  BuildTree tree_;
  float root_area_ = 0.0f;
  std::size_t budget_ = 0;
  std::size_t live_ = 0;  ///< references in existence now
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
