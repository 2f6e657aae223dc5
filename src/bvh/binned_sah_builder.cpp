// Binned SAH builder (Wald 2007): centroid binning per axis, split costed at bin boundaries, parallel subtrees.
// Binning and partitioning run four lanes at a time with SSE (every x86-64 CPU has it): a reference's box is loaded
// as two 4-float vectors, its bin on all three axes is computed at once, and bins are extended with SIMD min/max.
#include "rayaccel/bvh/binned_sah_builder.h"

#include <emmintrin.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <string>

#include "rayaccel/bvh/top_down_builder.h"
#include "rayaccel/core/error.h"

namespace rayaccel {

namespace {

constexpr std::uint32_t kMaxBins = 64;

// A reference's box is read as two unaligned 4-float loads: (lo.x, lo.y, lo.z, hi.x) and (hi.x, hi.y, hi.z, id).
// Only lanes 0..2 are ever used; lane 3 holds whatever follows and is ignored.
static_assert(offsetof(PrimRef, bounds) == 0 && offsetof(AABB, hi) == 3 * sizeof(float) &&
                  offsetof(PrimRef, prim_id) == 6 * sizeof(float) && sizeof(PrimRef) == 7 * sizeof(float),
              "PrimRef layout: six floats of bounds, then the id");

inline __m128 load_lo(const PrimRef& r) { return _mm_loadu_ps(&r.bounds.lo.x); }
/// Lane 3 (the id's bits) is zeroed so that it never enters arithmetic as a denormal.
inline __m128 load_hi(const PrimRef& r) {
  return _mm_and_ps(_mm_loadu_ps(&r.bounds.hi.x), _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1)));
}

/// Centroids are binned doubled (lo + hi: one add, no rounding of the halving), against bounds of doubled centroids.
struct BinMap {
  __m128 lo;       ///< lowest doubled centroid per axis
  __m128 scale;    ///< bins per unit of doubled centroid per axis; 0 on axes without extent
  __m128 last;     ///< bin_count - 1 in every lane

  /// Bin of the reference on each axis (lanes 0..2). The same float operations in binning and partitioning, so a
  /// reference always lands on the side its bin was counted on.
  __m128i bins_of(const PrimRef& r) const {
    const __m128 doubled_centroid = _mm_add_ps(load_lo(r), load_hi(r));
    __m128 f = _mm_mul_ps(_mm_sub_ps(doubled_centroid, lo), scale);
    f = _mm_max_ps(f, _mm_setzero_ps());  // NaN (0 * inf on a degenerate axis) becomes 0
    f = _mm_min_ps(f, last);
    return _mm_cvttps_epi32(f);
  }
};

/// Bins of all three axes side by side: box[i][a] is bin i on axis a, count[i][a] its reference count, so the sweep
/// handles the three axes in the lanes of one vector.
struct alignas(16) Bins {
  __m128 lo[kMaxBins][3];
  __m128 hi[kMaxBins][3];
  alignas(16) std::int32_t count[kMaxBins][4];

  void clear(std::uint32_t bin_count) {
    const __m128 inf = _mm_set1_ps(std::numeric_limits<float>::infinity());
    const __m128 minus_inf = _mm_set1_ps(-std::numeric_limits<float>::infinity());
    for (std::uint32_t i = 0; i < bin_count; ++i) {
      for (int a = 0; a < 3; ++a) {
        lo[i][a] = inf;
        hi[i][a] = minus_inf;
      }
      _mm_store_si128(reinterpret_cast<__m128i*>(count[i]), _mm_setzero_si128());
    }
  }
  __m128i counts(std::uint32_t i) const { return _mm_load_si128(reinterpret_cast<const __m128i*>(count[i])); }
};

AABB to_aabb(__m128 lo, __m128 hi) {
  alignas(16) float l[4], h[4];
  _mm_store_ps(l, lo);
  _mm_store_ps(h, hi);
  return {{l[0], l[1], l[2]}, {h[0], h[1], h[2]}};
}

/// Half the surface area of three boxes (lanes 0..2 of the result): box a is lo[a]..hi[a], lanes 0..2 x, y, z.
__m128 half_areas(const __m128 (&lo)[3], const __m128 (&hi)[3]) {
  __m128 x = _mm_sub_ps(hi[0], lo[0]);
  __m128 y = _mm_sub_ps(hi[1], lo[1]);
  __m128 z = _mm_sub_ps(hi[2], lo[2]);
  __m128 w = _mm_setzero_ps();
  _MM_TRANSPOSE4_PS(x, y, z, w);  // now x holds the three boxes' x extents, and so on
  return _mm_add_ps(_mm_add_ps(_mm_mul_ps(x, y), _mm_mul_ps(y, z)), _mm_mul_ps(z, x));
}

/// Running union of bins, one box per axis.
struct SweepBoxes {
  __m128 lo[3], hi[3];
  __m128i count = _mm_setzero_si128();
  SweepBoxes() {
    for (int a = 0; a < 3; ++a) {
      lo[a] = _mm_set1_ps(std::numeric_limits<float>::infinity());
      hi[a] = _mm_set1_ps(-std::numeric_limits<float>::infinity());
    }
  }
  void add(const Bins& bins, std::uint32_t i) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = _mm_min_ps(lo[a], bins.lo[i][a]);
      hi[a] = _mm_max_ps(hi[a], bins.hi[i][a]);
    }
    count = _mm_add_epi32(count, bins.counts(i));
  }
  /// half area * blocks per axis, where blocks = ceil(count / 2^block_shift)
  __m128 cost(int block_shift) const {
    const __m128i round_up = _mm_set1_epi32((1 << block_shift) - 1);
    const __m128i blocks = _mm_srl_epi32(_mm_add_epi32(count, round_up), _mm_cvtsi32_si128(block_shift));
    return _mm_mul_ps(half_areas(lo, hi), _mm_cvtepi32_ps(blocks));
  }
};

BinMap map_for(std::span<const PrimRef> refs, std::uint32_t bin_count) {
  __m128 lo = _mm_set1_ps(std::numeric_limits<float>::infinity());
  __m128 hi = _mm_set1_ps(-std::numeric_limits<float>::infinity());
  for (const PrimRef& r : refs) {
    const __m128 c = _mm_add_ps(load_lo(r), load_hi(r));
    lo = _mm_min_ps(lo, c);
    hi = _mm_max_ps(hi, c);
  }
  alignas(16) float l[4], h[4], s[4] = {0, 0, 0, 0};
  _mm_store_ps(l, lo);
  _mm_store_ps(h, hi);
  for (int a = 0; a < 3; ++a) {
    const float extent = h[a] - l[a];
    s[a] = extent > 0.0f ? static_cast<float>(bin_count) / extent : 0.0f;
  }
  return {lo, _mm_load_ps(s), _mm_set1_ps(static_cast<float>(bin_count - 1))};
}

}  // namespace

BinnedSplit find_binned_split(std::span<const PrimRef> refs, std::uint32_t bin_count, int block_shift) {
  BinnedSplit best;
  const BinMap map = map_for(refs, bin_count);
  // Reused per thread and cleared only as far as used: small nodes are many.
  thread_local Bins bins;
  bins.clear(bin_count);
  for (const PrimRef& r : refs) {
    alignas(16) std::int32_t index[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(index), map.bins_of(r));
    const __m128 lo = load_lo(r);
    const __m128 hi = load_hi(r);
    for (int a = 0; a < 3; ++a) {
      const int i = index[a];
      bins.lo[i][a] = _mm_min_ps(bins.lo[i][a], lo);
      bins.hi[i][a] = _mm_max_ps(bins.hi[i][a], hi);
      ++bins.count[i][a];
    }
  }
  // Axes that can be split: extent > 0 and a finite bin scale.
  alignas(16) float scale[4];
  _mm_store_ps(scale, map.scale);
  alignas(16) std::int32_t usable_axis[4] = {0, 0, 0, 0};
  for (int a = 0; a < 3; ++a) {
    usable_axis[a] = scale[a] != 0.0f && scale[a] < std::numeric_limits<float>::infinity() ? -1 : 0;
  }
  const __m128 usable = _mm_castsi128_ps(_mm_load_si128(reinterpret_cast<const __m128i*>(usable_axis)));
  // Right to left: the cost of everything right of each boundary, all three axes at once.
  alignas(16) float right_cost[kMaxBins][4];
  alignas(16) std::int32_t right_count[kMaxBins][4];
  SweepBoxes right;
  for (std::uint32_t i = bin_count - 1; i > 0; --i) {
    right.add(bins, i);
    _mm_store_ps(right_cost[i], right.cost(block_shift));
    _mm_store_si128(reinterpret_cast<__m128i*>(right_count[i]), right.count);
  }
  // Left to right: best boundary per axis (strict <: the first of equal costs wins, as in axis-then-bin order).
  SweepBoxes left;
  __m128 best_cost = _mm_set1_ps(std::numeric_limits<float>::infinity());
  __m128i best_bin = _mm_set1_epi32(-1);
  const __m128i zero = _mm_setzero_si128();
  for (std::uint32_t i = 0; i + 1 < bin_count; ++i) {
    left.add(bins, i);
    const __m128i right_n = _mm_load_si128(reinterpret_cast<const __m128i*>(right_count[i + 1]));
    const __m128 cost = _mm_add_ps(left.cost(block_shift), _mm_load_ps(right_cost[i + 1]));
    const __m128 both_sides = _mm_castsi128_ps(
        _mm_andnot_si128(_mm_or_si128(_mm_cmpeq_epi32(left.count, zero), _mm_cmpeq_epi32(right_n, zero)),
                         _mm_set1_epi32(-1)));
    const __m128 better = _mm_and_ps(_mm_and_ps(both_sides, usable), _mm_cmplt_ps(cost, best_cost));
    best_cost = _mm_or_ps(_mm_and_ps(better, cost), _mm_andnot_ps(better, best_cost));
    const __m128i better_i = _mm_castps_si128(better);
    best_bin = _mm_or_si128(_mm_and_si128(better_i, _mm_set1_epi32(static_cast<int>(i))),
                            _mm_andnot_si128(better_i, best_bin));
  }
  alignas(16) float axis_cost[4];
  alignas(16) std::int32_t axis_bin[4];
  _mm_store_ps(axis_cost, best_cost);
  _mm_store_si128(reinterpret_cast<__m128i*>(axis_bin), best_bin);
  for (int a = 0; a < 3; ++a) {
    if (axis_bin[a] < 0) continue;
    if (best.axis < 0 || axis_cost[a] < best.cost) {
      best.axis = a;
      best.bin = static_cast<std::uint32_t>(axis_bin[a]);
      best.cost = axis_cost[a];
    }
  }
  if (best.axis < 0) return best;
  best.cost *= 2.0f;  // half areas to surface areas (exact: a power of two)
  // The two sides' boxes and counts, gathered once for the winning boundary.
  const int a = best.axis;
  __m128 lo = _mm_set1_ps(std::numeric_limits<float>::infinity());
  __m128 hi = _mm_set1_ps(-std::numeric_limits<float>::infinity());
  for (std::uint32_t i = 0; i < bin_count; ++i) {
    if (i == best.bin + 1) {
      best.left = to_aabb(lo, hi);
      lo = _mm_set1_ps(std::numeric_limits<float>::infinity());
      hi = _mm_set1_ps(-std::numeric_limits<float>::infinity());
    }
    if (i <= best.bin) best.left_count += static_cast<std::uint32_t>(bins.count[i][a]);
    lo = _mm_min_ps(lo, bins.lo[i][a]);
    hi = _mm_max_ps(hi, bins.hi[i][a]);
  }
  best.right = to_aabb(lo, hi);
  alignas(16) float map_lo[4];
  _mm_store_ps(map_lo, map.lo);
  best.centroid_lo = map_lo[a];
  best.scale = scale[a];
  return best;
}

std::size_t partition_binned(std::span<PrimRef> refs, const BinnedSplit& split, std::uint32_t bin_count) {
  // Scalar SSE arithmetic, operation for operation the lane of BinMap::bins_of() for this axis: the same bins.
  const int a = split.axis;
  const float lo = split.centroid_lo;
  const float scale = split.scale;
  const auto last = static_cast<float>(bin_count - 1);
  const auto goes_left = [&](const PrimRef& r) {
    float f = (r.bounds.lo[a] + r.bounds.hi[a] - lo) * scale;
    f = f > 0.0f ? f : 0.0f;  // as _mm_max_ps(f, 0): NaN becomes 0
    f = f < last ? f : last;  // as _mm_min_ps(f, last)
    return static_cast<std::uint32_t>(static_cast<std::int32_t>(f)) <= split.bin;
  };
  std::size_t left = 0;
  std::size_t right = refs.size();
  for (;;) {
    while (left < right && goes_left(refs[left])) ++left;
    while (left < right && !goes_left(refs[right - 1])) --right;
    if (left >= right) break;
    std::swap(refs[left], refs[right - 1]);
    ++left;
    --right;
  }
  return left;
}

BuildTree build_binned_sah(PrimRefs refs, const BinnedSahOptions& config) {
  if (config.bin_count < 2 || config.bin_count > kMaxBins) {
    throw Error("binned SAH: bin count " + std::to_string(config.bin_count) + " is outside 2.." +
                std::to_string(kMaxBins));
  }
  if (config.block_size < 1 || config.block_size > 64 || (config.block_size & (config.block_size - 1)) != 0) {
    throw Error("binned SAH: block size " + std::to_string(config.block_size) + " is not a power of two in 1..64");
  }
  const int block_shift = __builtin_ctz(config.block_size);
  const TopDownLimits limits{config.max_leaf_size, config.parallel_threshold};
  // A node of at most one block, when a traversal step costs at least a block test, is a leaf whatever the split:
  // splitting costs at least the traversal step, the leaf one block test. Such nodes are not binned at all.
  const std::size_t always_leaf = config.costs.intersection <= config.costs.traversal
                                      ? std::min<std::size_t>(config.max_leaf_size, config.block_size)
                                      : 0;
  return build_top_down(std::move(refs), limits, [&](std::uint32_t, std::span<PrimRef> node_refs) -> std::size_t {
    if (node_refs.size() <= always_leaf) return 0;
    const BinnedSplit split = find_binned_split(node_refs, config.bin_count, block_shift);
    if (split.axis < 0) return 0;
    const float area = merge(split.left, split.right).surface_area();
    if (sah_prefers_leaf(node_refs.size(), area, split.cost, config.max_leaf_size, config.costs, block_shift)) {
      return 0;
    }
    return partition_binned(node_refs, split, config.bin_count);
  });
}

}  // namespace rayaccel
