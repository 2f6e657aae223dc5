// Binned SAH builder (Wald 2007): centroid binning per axis, split costed at bin boundaries, parallel subtrees.
// Binning and partitioning run four lanes at a time with SSE (every x86-64 CPU has it): a reference's box is loaded
// as two 4-float vectors, its bin on all three axes is computed at once, and bins are extended with SIMD min/max.
#include "rayaccel/bvh/binned_sah_builder.h"

#include <emmintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>

#include "rayaccel/bvh/top_down_builder.h"
#include "rayaccel/core/error.h"

namespace rayaccel {

namespace {

constexpr std::uint32_t kMaxBins = 64;
/// Nodes of at least this many references are binned (and their centroid bounds found) by several threads, in
/// chunks of kParallelChunk; below it a task's overhead outweighs the work. Bins merge exactly (min, max and integer
/// sums), so the split, and the tree, are those of the serial pass whatever the thread count.
constexpr std::size_t kParallelBinning = std::size_t{1} << 15;
constexpr std::size_t kParallelChunk = std::size_t{1} << 13;

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
  void merge(const Bins& other, std::uint32_t bin_count) {
    for (std::uint32_t i = 0; i < bin_count; ++i) {
      for (int a = 0; a < 3; ++a) {
        lo[i][a] = _mm_min_ps(lo[i][a], other.lo[i][a]);
        hi[i][a] = _mm_max_ps(hi[i][a], other.hi[i][a]);
      }
      _mm_store_si128(reinterpret_cast<__m128i*>(count[i]), _mm_add_epi32(counts(i), other.counts(i)));
    }
  }
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

/// Bounds of the references' doubled centroids (lanes 0..2; lane 3 unused): what the bins are laid over.
struct CentroidBox {
  __m128 lo = _mm_set1_ps(std::numeric_limits<float>::infinity());
  __m128 hi = _mm_set1_ps(-std::numeric_limits<float>::infinity());
  bool known = false;  ///< false: not yet found (the hint of the root and after a median split)

  void extend(__m128 c) {
    lo = _mm_min_ps(lo, c);
    hi = _mm_max_ps(hi, c);
  }
  void extend(const CentroidBox& b) {
    lo = _mm_min_ps(lo, b.lo);
    hi = _mm_max_ps(hi, b.hi);
  }
};

inline __m128 doubled_centroid(const PrimRef& r) { return _mm_add_ps(load_lo(r), load_hi(r)); }

CentroidBox centroid_box_of(std::span<const PrimRef> refs) {
  const auto serial = [](std::span<const PrimRef> part) {
    CentroidBox box;
    for (const PrimRef& r : part) box.extend(doubled_centroid(r));
    return box;
  };
  if (refs.size() < kParallelBinning) return serial(refs);
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, refs.size(), kParallelChunk), CentroidBox{},
      [&](const tbb::blocked_range<std::size_t>& r, CentroidBox box) {
        box.extend(serial(refs.subspan(r.begin(), r.size())));
        return box;
      },
      [](CentroidBox a, const CentroidBox& b) {
        a.extend(b);
        return a;
      });
}

BinMap map_for(const CentroidBox& centroids, std::uint32_t bin_count) {
  alignas(16) float l[4], h[4], s[4] = {0, 0, 0, 0};
  _mm_store_ps(l, centroids.lo);
  _mm_store_ps(h, centroids.hi);
  for (int a = 0; a < 3; ++a) {
    const float extent = h[a] - l[a];
    s[a] = extent > 0.0f ? static_cast<float>(bin_count) / extent : 0.0f;
  }
  return {centroids.lo, _mm_load_ps(s), _mm_set1_ps(static_cast<float>(bin_count - 1))};
}

/// Adds refs to the bins laid out by `map`.
void bin_references(std::span<const PrimRef> refs, const BinMap& map, Bins& bins) {
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
}

/// The bins of refs, in `bins` (cleared here): one pass by this thread, or for large nodes one per thread over
/// chunks, merged. The caller's thread may run other nodes' splits while it waits for the chunks, so `bins` must not
/// be the thread's reused bins then.
void bin_all(std::span<const PrimRef> refs, const BinMap& map, std::uint32_t bin_count, Bins& bins) {
  bins.clear(bin_count);
  if (refs.size() < kParallelBinning) {
    bin_references(refs, map, bins);
    return;
  }
  tbb::combinable<Bins> partial([bin_count] {
    Bins b;
    b.clear(bin_count);
    return b;
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, refs.size(), kParallelChunk),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      bin_references(refs.subspan(r.begin(), r.size()), map, partial.local());
                    });
  partial.combine_each([&](const Bins& b) { bins.merge(b, bin_count); });
}

/// The best split of refs whose doubled centroids lie in `centroids`.
BinnedSplit find_split(std::span<const PrimRef> refs, const CentroidBox& centroids, std::uint32_t bin_count,
                       int block_shift) {
  BinnedSplit best;
  const BinMap map = map_for(centroids, bin_count);
  // Small nodes are many: their bins are reused per thread (and cleared only as far as used). Large ones wait for
  // other threads, during which this thread may bin another node, so theirs are their own.
  thread_local Bins reused;
  std::unique_ptr<Bins> own;
  if (refs.size() >= kParallelBinning) own = std::make_unique<Bins>();
  Bins& bins = own ? *own : reused;
  bin_all(refs, map, bin_count, bins);
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

}  // namespace

BinnedSplit find_binned_split(std::span<const PrimRef> refs, std::uint32_t bin_count, int block_shift) {
  return find_split(refs, centroid_box_of(refs), bin_count, block_shift);
}

namespace {

/// Partitions refs by `split` (Hoare's scheme) and returns the size of the left side; with Centroids, also the
/// bounds of each side's doubled centroids, so the children need no pass of their own to find them.
template <bool Centroids>
std::size_t partition_refs(std::span<PrimRef> refs, const BinnedSplit& split, std::uint32_t bin_count,
                           CentroidBox* left_box, CentroidBox* right_box) {
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
  CentroidBox lbox, rbox;
  std::size_t left = 0;
  std::size_t right = refs.size();
  for (;;) {
    while (left < right && goes_left(refs[left])) {
      if constexpr (Centroids) lbox.extend(doubled_centroid(refs[left]));
      ++left;
    }
    while (left < right && !goes_left(refs[right - 1])) {
      if constexpr (Centroids) rbox.extend(doubled_centroid(refs[right - 1]));
      --right;
    }
    if (left >= right) break;
    // refs[left] goes right and refs[right - 1] left: swapped, each is on its side.
    if constexpr (Centroids) {
      rbox.extend(doubled_centroid(refs[left]));
      lbox.extend(doubled_centroid(refs[right - 1]));
    }
    std::swap(refs[left], refs[right - 1]);
    ++left;
    --right;
  }
  if constexpr (Centroids) {
    *left_box = lbox;
    *right_box = rbox;
    left_box->known = right_box->known = true;
  }
  return left;
}

}  // namespace

std::size_t partition_binned(std::span<PrimRef> refs, const BinnedSplit& split, std::uint32_t bin_count) {
  return partition_refs<false>(refs, split, bin_count, nullptr, nullptr);
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
  // Each split finds its children's centroid bounds while partitioning (the hint), so a node's references are read
  // twice (binning, partitioning) rather than three times.
  return build_top_down_hinted<CentroidBox>(
      std::move(refs), limits,
      [&](std::uint32_t, std::span<PrimRef> node_refs, const CentroidBox& hint, CentroidBox& left_hint,
          CentroidBox& right_hint) -> std::size_t {
        if (node_refs.size() <= always_leaf) return 0;
        const BinnedSplit split =
            find_split(node_refs, hint.known ? hint : centroid_box_of(node_refs), config.bin_count, block_shift);
        if (split.axis < 0) return 0;
        const float area = merge(split.left, split.right).surface_area();
        if (sah_prefers_leaf(node_refs.size(), area, split.cost, config.max_leaf_size, config.costs, block_shift)) {
          return 0;
        }
        return partition_refs<true>(node_refs, split, config.bin_count, &left_hint, &right_hint);
      });
}

}  // namespace rayaccel
