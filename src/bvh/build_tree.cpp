// Helpers every BVH builder shares: bounds of reference ranges and the median split that bounds depth.
#include "rayaccel/bvh/build_tree.h"

#include <algorithm>

namespace rayaccel {

AABB bounds_of(std::span<const PrimRef> refs) {
  AABB box;
  for (const PrimRef& r : refs) box.extend(r.bounds);
  return box;
}

AABB centroid_bounds_of(std::span<const PrimRef> refs) {
  AABB box;
  for (const PrimRef& r : refs) box.extend(r.centroid());
  return box;
}

std::size_t split_at_median(std::span<PrimRef> refs) {
  const int axis = centroid_bounds_of(refs).largest_axis();
  const std::size_t mid = refs.size() / 2;
  std::nth_element(refs.begin(), refs.begin() + static_cast<std::ptrdiff_t>(mid), refs.end(),
                   [axis](const PrimRef& a, const PrimRef& b) {
                     const float ca = a.bounds.lo[axis] + a.bounds.hi[axis];
                     const float cb = b.bounds.lo[axis] + b.bounds.hi[axis];
                     return ca < cb || (ca == cb && a.prim_id < b.prim_id);
                   });
  return mid;
}

void build_median_subtree(BuildTree& tree, std::uint32_t node, std::uint32_t first, std::uint32_t count,
                          std::uint32_t max_leaf_size) {
  if (count <= max_leaf_size) {
    tree.nodes[node] = {first, count};
    return;
  }
  const auto left_count =
      static_cast<std::uint32_t>(split_at_median(std::span<PrimRef>(tree.refs).subspan(first, count)));
  const auto left = static_cast<std::uint32_t>(tree.nodes.size());
  tree.nodes.resize(tree.nodes.size() + 2);
  tree.nodes[node] = {left, 0};
  build_median_subtree(tree, left, first, left_count, max_leaf_size);
  build_median_subtree(tree, left + 1, first + left_count, count - left_count, max_leaf_size);
}

}  // namespace rayaccel
