// Heat maps of traversal cost: the cost of a ray (nodes visited + primitives tested), its place on a linear scale
// from the image's cheapest ray to its 99th-percentile cost (a few grazing silhouette rays would otherwise squeeze
// everything else into the dark end), and the legend (colour bar with the numeric range) drawn into the image.
#pragma once

#include <cstdint>
#include <span>

#include "rayaccel/core/stats.h"
#include "rayaccel/render/image.h"

namespace rayaccel {

/// Cost of one ray: nodes (or cells) entered plus primitives tested.
inline std::uint64_t traversal_cost(const TraversalStats& s) { return s.nodes_visited + s.primitives_tested; }

struct CostRange {
  std::uint64_t min = 0;      ///< bottom of the scale: the cheapest ray
  std::uint64_t max = 0;      ///< top of the scale; dearer rays are clamped to its colour
  std::uint64_t highest = 0;  ///< the dearest ray (> max when the scale is clipped)
};

/// Fraction of rays whose cost sets the top of the scale.
inline constexpr double kHeatScalePercentile = 0.99;

/// min = the smallest cost, max = the kHeatScalePercentile quantile (the cost at sorted position
/// floor(0.99 * (n - 1))), highest = the largest; all 0 when empty.
CostRange cost_range(std::span<const TraversalStats> stats);
/// (cost - min) / (max - min) clamped to [0, 1]; 0.5 when the range is a single value (no ray is cheaper or
/// dearer than another, so every pixel takes the middle of the ramp).
float cost_fraction(std::uint64_t cost, const CostRange& range);

/// Height in pixels of the legend panel for an image of this size.
int heat_legend_height(int width, int height);
/// Draws the legend into the bottom heat_legend_height() rows: a dark panel holding a colour bar of heat_colour()
/// from min (left) to max (right), the min cost under its left end, the max cost under its right end ("+" appended
/// when the scale is clipped), and a caption centered between them: the longest of "COST = NODES+PRIMS, MAX n",
/// "COST, MAX n", "MAX n" (these three only when clipped, n = highest) and "COST" that fits. Everything is
/// clipped to the image.
/// Images less than three legend heights tall get no legend (it would hide most of the picture).
void draw_heat_legend(Image& image, const CostRange& range);

}  // namespace rayaccel
