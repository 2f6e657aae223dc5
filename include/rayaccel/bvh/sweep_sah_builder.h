// Full sweep SAH builder (MacDonald & Booth 1990; as evaluated by Wald 2007): at every node the references are
// sorted by centroid on each axis and every split position is costed. Higher quality than binning, O(n log^2 n).
#pragma once

#include <cstdint>
#include <vector>

#include "rayaccel/bvh/build_tree.h"

namespace rayaccel {

struct SweepSahOptions {
  std::uint32_t max_leaf_size = 4;          ///< largest leaf; smaller leaves are made when the SAH prefers them
  SahCosts costs;                           ///< traversal 1, intersection 1
  std::uint32_t parallel_threshold = 4096;  ///< subtrees of at least this many references are built as parallel tasks
};

BuildTree build_sweep_sah(PrimRefs refs, const SweepSahOptions& config);

}  // namespace rayaccel
