// LBVH builder (Lauterbach, Garland, Sengupta, Luebke, Manocha 2009, "Fast BVH Construction on GPUs"): references
// sorted by Morton code, then split recursively where the highest differing code bit changes (the sorted-split
// recursion; Karras 2012 emits the same hierarchy in parallel).
#pragma once

#include <cstdint>
#include <vector>

#include "rayaccel/bvh/build_tree.h"

namespace rayaccel {

struct LbvhOptions {
  std::uint32_t max_leaf_size = 4;          ///< ranges of at most this many references become leaves
  std::uint32_t parallel_threshold = 4096;  ///< subtrees of at least this many references are built as parallel tasks
};

BuildTree build_lbvh(PrimRefs refs, const LbvhOptions& config);

}  // namespace rayaccel
