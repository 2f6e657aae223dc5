// Heat maps of traversal cost (nodes visited + primitives tested) on a linear scale from the cheapest ray to the
// 99th percentile, or one scale several images share, with a legend drawn into the image.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

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
CostRange cost_range(std::span<const std::uint64_t> costs);
/// (cost - min) / (max - min) clamped to [0, 1]; 0.5 when the range is a single value (no ray is cheaper or
/// dearer than another, so every pixel takes the middle of the ramp).
float cost_fraction(std::uint64_t cost, const CostRange& range);

/// Height in pixels of the legend panel for an image of this size.
int heat_legend_height(int width, int height);
/// Draws the legend into the bottom heat_legend_height() rows: a dark panel holding a colour bar of heat_colour()
/// from min (left) to max (right), the min cost under its left end, the max cost under its right end ("+" appended
/// when the scale is clipped), and a caption centered between them: the longest of "FULL, MAX n", "WORD, MAX n",
/// "MAX n" (these three only when clipped, n = highest) and "WORD" that fits (FULL and WORD from `caption`:
/// "COST = NODES+PRIMS" and "COST" by default). Everything is
/// clipped to the image.
/// Images less than three legend heights tall get no legend (it would hide most of the picture).
/// What the legend calls the quantity: a full caption and a one-word form for narrow images.
struct HeatCaption {
  std::string full = "COST = NODES+PRIMS";
  std::string word = "COST";
};
void draw_heat_legend(Image& image, const CostRange& range, const HeatCaption& caption = {});

/// What a heat map is drawn from, kept apart from the image so several maps can be drawn on one scale afterwards.
struct HeatFrame {
  int width = 0;
  int height = 0;
  std::vector<std::uint64_t> cost;  ///< traversal_cost() per pixel, row by row
  std::vector<float> brightness;    ///< per pixel: 1 at misses, 0.6 to 0.9 at hits (by how squarely the ray meets)
  CostRange range;                  ///< cost_range() of this frame alone
};

/// Bytes per pixel that keeping HeatFrames and then taking their shared_cost_range() needs.
inline constexpr std::size_t kSharedHeatBytesPerPixel = 2 * sizeof(std::uint64_t) + sizeof(float);

/// One scale for several images, so that equal costs get equal colours in every one: cost_range() of all their
/// pixels pooled (an image whose rays all cost more than the pooled 99th percentile, brute force's beside a BVH's,
/// shows as clipped rather than pushing every other image into the dark end). All 0 when there are no pixels.
CostRange shared_cost_range(std::span<const HeatFrame* const> frames);

/// The heat map of `frame` on `scale`: heat_colour(cost_fraction(cost, scale)) times the pixel's brightness, and
/// the legend of `scale` with the frame's own highest cost (so "+" marks exactly the frames that are clipped).
Image draw_heat_frame(const HeatFrame& frame, const CostRange& scale, const HeatCaption& caption = {});

}  // namespace rayaccel
