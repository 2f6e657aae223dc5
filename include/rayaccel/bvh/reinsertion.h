// Insertion-based optimisation of a built binary tree (Bittner, Hapala & Havran 2013, "Fast insertion-based
// optimization of bounding volume hierarchies"): subtrees are taken out and put back where the SAH cost is least.
#pragma once

#include <cstdint>

#include "rayaccel/bvh/build_tree.h"

namespace rayaccel {

struct ReinsertionOptions {
  SahCosts costs;
  std::uint32_t block_size = 1;     ///< leaves priced per started block of this many (a power of two), as the builders
  std::uint32_t max_batches = 16;   ///< rounds of selection and reinsertion at most
  float batch_fraction = 0.02f;     ///< interior nodes whose children are reinserted per round, of all interior nodes
  float min_gain = 0.002f;          ///< stop after a round that lowers the cost by less than this fraction
};

struct ReinsertionResult {
  double cost_before = 0.0, cost_after = 0.0;  ///< SAH cost (area-weighted, unnormalised) before and after
  std::uint32_t batches = 0;                    ///< rounds run
  std::uint32_t moves = 0;                      ///< subtrees put back somewhere other than where they were
};

/// Optimises `tree` in place: each round takes the interior nodes that bound their children worst (the product of
/// Bittner et al.'s three measures: area, area over the children's mean and over their least), takes each of their
/// two children out in turn and reinserts it beside the node where it adds the least SAH cost (a branch-and-bound
/// search from the root), until a round gains too little. Leaves keep their references (refs is unchanged); the node
/// array is rewritten, children after their parent and siblings side by side. The cost never rises (the old place is
/// among those searched); a tree that would grow deeper than the traversal stack allows is left as it was.
ReinsertionResult reinsert_nodes(BuildTree& tree, const ReinsertionOptions& options);

}  // namespace rayaccel
