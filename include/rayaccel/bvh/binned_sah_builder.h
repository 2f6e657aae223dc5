// Binned SAH builder (Wald 2007, "On fast Construction of SAH-based Bounding Volume Hierarchies"): centroids are
// binned along each axis and the split is chosen among the bin boundaries; subtrees are built in parallel (TBB).
#pragma once

#include <cstdint>
#include <vector>

#include "rayaccel/bvh/build_tree.h"

namespace rayaccel {

struct BinnedSahOptions {
  std::uint32_t max_leaf_size = 4;          ///< largest leaf; smaller leaves are made when the SAH prefers them
  SahCosts costs;                           ///< traversal 1, intersection 1
  std::uint32_t bin_count = 16;             ///< bins per axis, 2..64 (Wald uses 8 to 32)
  std::uint32_t parallel_threshold = 4096;  ///< subtrees of at least this many references are built as parallel tasks
  /// References a leaf tests at once (a power of two, 1..64): the SAH charges `costs.intersection` per started block
  /// of this many, as for SIMD leaves that test four triangles for the price of one (block_size 4).
  std::uint32_t block_size = 1;
};

/// Builds from references (boxes and ids only). Throws Error for a bin_count outside 2..64.
BuildTree build_binned_sah(PrimRefs refs, const BinnedSahOptions& config);

}  // namespace rayaccel

namespace rayaccel {

/// The best object split found by binning centroids (also used by the SBVH builder).
struct BinnedSplit {
  int axis = -1;             ///< -1 when no split exists (all centroids equal)
  std::uint32_t bin = 0;     ///< references in bins 0..bin go left
  float cost = 0.0f;         ///< area(left) * blocks(left) + area(right) * blocks(right); blocks = counts when shift 0
  AABB left, right;          ///< bounds of each side
  std::uint32_t left_count = 0;
  float centroid_lo = 0.0f;  ///< lower bound on `axis` of the doubled centroids (lo + hi) that were binned
  float scale = 0.0f;        ///< bins per unit of doubled centroid on `axis`
};

/// Best bin boundary by the SAH, counting references in blocks of 2^block_shift (0: one by one).
BinnedSplit find_binned_split(std::span<const PrimRef> refs, std::uint32_t bin_count, int block_shift = 0);
/// Partitions refs by `split` and returns the size of the left side (split.left_count).
std::size_t partition_binned(std::span<PrimRef> refs, const BinnedSplit& split, std::uint32_t bin_count);

}  // namespace rayaccel
