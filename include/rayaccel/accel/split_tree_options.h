// The options the kd-tree and the BSP tree share (both SAH split trees traversed by segments): max_depth, leaf_size
// and the SAH constants K_T and K_I, as rows of their option tables. Each tree words the docs for its own build.
#pragma once

#include <string>

#include "rayaccel/accel/option_table.h"
#include "rayaccel/accel/segment_traversal.h"

namespace rayaccel {

template <class O>
void add_split_tree_options(OptionTable<O>& table, std::string leaf_size_doc, std::string traversal_cost_doc,
                            std::string intersection_cost_doc) {
  table.integer("max_depth", &O::max_depth, 0, kMaxSplitTreeDepth, "deepest leaf; 0 = round(8 + 1.3 log2 n)");
  table.integer("leaf_size", &O::leaf_size, 1, 1 << 20, std::move(leaf_size_doc));
  table.real("traversal_cost", &O::traversal_cost, RealRange::positive(), std::move(traversal_cost_doc));
  table.real("intersection_cost", &O::intersection_cost, RealRange::positive(), std::move(intersection_cost_doc));
}

}  // namespace rayaccel
