// Full sweep SAH builder: every centroid-sorted split position on every axis is costed (MacDonald & Booth 1990).
#include "rayaccel/bvh/sweep_sah_builder.h"

#include <algorithm>

#include "rayaccel/bvh/top_down_builder.h"

namespace rayaccel {

namespace {

void sort_on_axis(std::span<PrimRef> refs, int axis) {
  std::sort(refs.begin(), refs.end(), [axis](const PrimRef& a, const PrimRef& b) {
    const float ca = a.bounds.lo[axis] + a.bounds.hi[axis];
    const float cb = b.bounds.lo[axis] + b.bounds.hi[axis];
    return ca < cb || (ca == cb && a.prim_id < b.prim_id);
  });
}

std::size_t sweep_split(std::span<PrimRef> refs, const SweepSahOptions& config) {
  const std::size_t n = refs.size();
  std::vector<float> right_area(n);
  int best_axis = -1;
  std::size_t best_left = 0;
  float best_cost = 0.0f;
  for (int axis = 0; axis < 3; ++axis) {
    sort_on_axis(refs, axis);
    AABB acc;
    for (std::size_t i = n; i-- > 1;) {
      acc.extend(refs[i].bounds);
      right_area[i] = acc.surface_area() * static_cast<float>(n - i);
    }
    AABB left;
    for (std::size_t i = 1; i < n; ++i) {
      left.extend(refs[i - 1].bounds);
      const float cost = left.surface_area() * static_cast<float>(i) + right_area[i];
      if (best_axis < 0 || cost < best_cost) {
        best_axis = axis;
        best_left = i;
        best_cost = cost;
      }
    }
  }
  const float area = bounds_of(refs).surface_area();
  if (best_axis < 0 || sah_prefers_leaf(n, area, best_cost, config.max_leaf_size, config.costs)) return 0;
  if (best_axis != 2) sort_on_axis(refs, best_axis);
  return best_left;
}

}  // namespace

BuildTree build_sweep_sah(PrimRefs refs, const SweepSahOptions& config) {
  const TopDownLimits limits{config.max_leaf_size, config.parallel_threshold};
  return build_top_down(std::move(refs), limits,
                        [&](std::uint32_t, std::span<PrimRef> node_refs) { return sweep_split(node_refs, config); });
}

}  // namespace rayaccel
