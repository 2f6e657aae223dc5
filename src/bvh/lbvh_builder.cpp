// LBVH: Morton-sorted references split at the highest differing code bit (Lauterbach et al. 2009).
#include "rayaccel/bvh/lbvh_builder.h"

#include <algorithm>
#include <bit>

#include "rayaccel/bvh/morton.h"
#include "rayaccel/bvh/top_down_builder.h"

namespace rayaccel {

BuildTree build_lbvh(PrimRefs refs, const LbvhOptions& config) {
  const std::vector<std::uint64_t> codes = sort_by_morton_code(refs);
  const TopDownLimits limits{config.max_leaf_size, config.parallel_threshold};
  // Equal codes make split() ask for a leaf; the median split the driver falls back to only reorders references
  // whose codes are all equal, so `codes` stays aligned with the references.
  return build_top_down(std::move(refs), limits, [&](std::uint32_t first, std::span<PrimRef> node_refs) -> std::size_t {
    if (node_refs.size() <= config.max_leaf_size) return 0;
    const auto begin = codes.begin() + first;
    const auto end = begin + static_cast<std::ptrdiff_t>(node_refs.size());
    const std::uint64_t differing = *begin ^ *(end - 1);
    if (differing == 0) return 0;
    const std::uint64_t bit = std::uint64_t{1} << (63 - std::countl_zero(differing));
    const auto split = std::partition_point(begin, end, [bit](std::uint64_t code) { return (code & bit) == 0; });
    return static_cast<std::size_t>(split - begin);
  });
}

}  // namespace rayaccel
