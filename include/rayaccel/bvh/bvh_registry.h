// Registry entry "bvh": every bounding volume x builder combination, chosen by options bv= and builder=.
#pragma once

#include <vector>

#include "rayaccel/accel/registry.h"

namespace rayaccel {

/// Adds "bvh" (options bv, builder, leaf_size, traversal_cost, intersection_cost, bins, max_growth, overlap_alpha,
/// ploc_radius) with one variant per volume x builder.
void register_bvh(std::vector<AcceleratorInfo>& registry);

}  // namespace rayaccel
