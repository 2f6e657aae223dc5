// PLOC builder (Meister & Bittner 2018, "Parallel Locally-Ordered Clustering for Bounding Volume Hierarchy
// Construction"): clusters in Morton order repeatedly merge with their mutual nearest neighbour (smallest merged
// box area) within a window; the resulting binary tree is collapsed into leaves where the SAH prefers them.
#pragma once

#include <cstdint>
#include <vector>

#include "rayaccel/bvh/build_tree.h"

namespace rayaccel {

struct PlocOptions {
  std::uint32_t max_leaf_size = 4;  ///< largest leaf made when collapsing subtrees
  SahCosts costs;                   ///< traversal 1, intersection 1: decide which subtrees become leaves
  std::uint32_t search_radius = 16; ///< neighbours searched on each side in Morton order (the paper's r)
};

BuildTree build_ploc(PrimRefs refs, const PlocOptions& config);

}  // namespace rayaccel
