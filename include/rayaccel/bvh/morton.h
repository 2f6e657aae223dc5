// Morton (Z-order) codes of reference centroids, the ordering behind the LBVH (Lauterbach et al. 2009) and PLOC
// (Meister & Bittner 2018) builders.
#pragma once

#include <cstdint>
#include <vector>

#include "rayaccel/core/primitives.h"

namespace rayaccel {

/// Sorts refs by the 63-bit Morton code of their centroid (21 bits per axis, quantized in the centroid bounds; ties
/// by primitive id) and returns the codes in the new order. Parallel (TBB).
std::vector<std::uint64_t> sort_by_morton_code(PrimRefs& refs);

}  // namespace rayaccel
