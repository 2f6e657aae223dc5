// Binned SAH builder (Wald 2007): centroid binning per axis, split costed at bin boundaries, parallel subtrees.
#include "rayaccel/bvh/binned_sah_builder.h"

#include <algorithm>
#include <array>
#include <string>

#include "rayaccel/bvh/top_down_builder.h"
#include "rayaccel/core/error.h"

namespace rayaccel {

namespace {

constexpr std::uint32_t kMaxBins = 64;

struct Bin {
  AABB box;
  std::uint32_t count = 0;
};

std::uint32_t bin_of(float centroid, float lo, float scale, std::uint32_t bin_count) {
  const auto k = static_cast<std::uint32_t>(std::max(0.0f, (centroid - lo) * scale));
  return std::min(k, bin_count - 1);
}

}  // namespace

BinnedSplit find_binned_split(std::span<const PrimRef> refs, std::uint32_t bin_count) {
  BinnedSplit best;
  const AABB centroids = centroid_bounds_of(refs);
  // Reused per thread and cleared only as far as used: small nodes are many, so a fresh 3 x 64-bin array each
  // would cost more than the binning itself.
  thread_local std::vector<Bin> storage;
  storage.assign(3 * std::size_t{bin_count}, Bin{});
  Bin* bins[3] = {storage.data(), storage.data() + bin_count, storage.data() + 2 * bin_count};
  std::array<float, 3> scale{};
  for (int a = 0; a < 3; ++a) {
    const float extent = centroids.hi[a] - centroids.lo[a];
    scale[a] = extent > 0.0f ? static_cast<float>(bin_count) / extent : 0.0f;
  }
  for (const PrimRef& r : refs) {
    const Vec3 c = r.centroid();
    for (int a = 0; a < 3; ++a) {
      Bin& b = bins[a][bin_of(c[a], centroids.lo[a], scale[a], bin_count)];
      b.box.extend(r.bounds);
      ++b.count;
    }
  }
  std::array<float, kMaxBins> right_area;
  thread_local std::vector<AABB> right_box;
  right_box.resize(bin_count);
  for (int a = 0; a < 3; ++a) {
    if (scale[a] == 0.0f || !(scale[a] < std::numeric_limits<float>::infinity())) continue;
    AABB acc;
    std::uint32_t right_count = 0;
    std::array<std::uint32_t, kMaxBins> right_counts;
    right_counts[0] = 0;
    for (std::uint32_t i = bin_count - 1; i > 0; --i) {
      acc.extend(bins[a][i].box);
      right_count += bins[a][i].count;
      right_box[i] = acc;
      right_area[i] = acc.surface_area() * static_cast<float>(right_count);
      right_counts[i] = right_count;
    }
    AABB left;
    std::uint32_t left_count = 0;
    for (std::uint32_t i = 0; i + 1 < bin_count; ++i) {
      left.extend(bins[a][i].box);
      left_count += bins[a][i].count;
      if (left_count == 0 || right_counts[i + 1] == 0) continue;
      const float cost = left.surface_area() * static_cast<float>(left_count) + right_area[i + 1];
      if (best.axis < 0 || cost < best.cost) {
        best.axis = a;
        best.bin = i;
        best.cost = cost;
        best.left = left;
        best.right = right_box[i + 1];
        best.left_count = left_count;
        best.centroid_lo = centroids.lo[a];
        best.scale = scale[a];
      }
    }
  }
  return best;
}

std::size_t partition_binned(std::span<PrimRef> refs, const BinnedSplit& split, std::uint32_t bin_count) {
  const auto mid = std::partition(refs.begin(), refs.end(), [&](const PrimRef& r) {
    return bin_of(r.centroid()[split.axis], split.centroid_lo, split.scale, bin_count) <= split.bin;
  });
  return static_cast<std::size_t>(mid - refs.begin());
}

BuildTree build_binned_sah(std::vector<PrimRef> refs, const BinnedSahConfig& config) {
  if (config.bin_count < 2 || config.bin_count > kMaxBins) {
    throw Error("binned SAH: bin count " + std::to_string(config.bin_count) + " is outside 2.." +
                std::to_string(kMaxBins));
  }
  const TopDownLimits limits{config.max_leaf_size, config.parallel_threshold};
  return build_top_down(std::move(refs), limits, [&](std::uint32_t, std::span<PrimRef> node_refs) -> std::size_t {
    const BinnedSplit split = find_binned_split(node_refs, config.bin_count);
    if (split.axis < 0) return 0;
    const float area = merge(split.left, split.right).surface_area();
    if (sah_prefers_leaf(node_refs.size(), area, split.cost, config.max_leaf_size, config.costs)) return 0;
    return partition_binned(node_refs, split, config.bin_count);
  });
}

}  // namespace rayaccel
