// Heat-map scale and legend: the colour bar and numeric labels drawn with the bitmap font.
#include "rayaccel/render/heatmap.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "rayaccel/core/error.h"
#include "rayaccel/render/bitmap_font.h"
#include "rayaccel/render/colormap.h"

namespace rayaccel {

namespace {

constexpr Rgb kPanel{16, 16, 20};
constexpr Rgb kText{240, 240, 240};

/// Legend pixels per font pixel: 1 up to 383 pixels on the short side, then one more per 256.
int legend_scale(int width, int height) { return std::max(1, (std::min(width, height) + 128) / 256); }

}  // namespace

CostRange cost_range(std::span<const TraversalStats> stats) {
  std::vector<std::uint64_t> costs(stats.size());
  std::transform(stats.begin(), stats.end(), costs.begin(), traversal_cost);
  return cost_range(costs);
}

CostRange cost_range(std::span<const std::uint64_t> costs_in) {
  if (costs_in.empty()) return {};
  std::vector<std::uint64_t> costs(costs_in.begin(), costs_in.end());
  const auto [lowest, highest] = std::minmax_element(costs.begin(), costs.end());
  CostRange r{*lowest, 0, *highest};
  const auto quantile = costs.begin() + static_cast<std::ptrdiff_t>(kHeatScalePercentile * (costs.size() - 1));
  std::nth_element(costs.begin(), quantile, costs.end());
  r.max = *quantile;
  return r;
}

float cost_fraction(std::uint64_t cost, const CostRange& range) {
  if (range.max <= range.min) return 0.5f;
  const double f = (static_cast<double>(cost) - static_cast<double>(range.min)) /
                   (static_cast<double>(range.max) - static_cast<double>(range.min));
  return static_cast<float>(std::clamp(f, 0.0, 1.0));
}

int heat_legend_height(int width, int height) {
  const int s = legend_scale(width, height);
  return 3 * s + 8 * s + 2 * s + kGlyphHeight * s + 3 * s;  // margin, bar, gap, labels, margin
}

void draw_heat_legend(Image& image, const CostRange& range, const HeatCaption& caption) {
  const int s = legend_scale(image.width, image.height);
  const int margin = 3 * s;
  const int legend_height = heat_legend_height(image.width, image.height);
  if (3 * legend_height > image.height) return;
  const int top = image.height - legend_height;
  image.fill_rect(0, top, image.width, image.height - top, kPanel);

  const int bar_x = margin, bar_y = top + margin, bar_w = std::max(1, image.width - 2 * margin), bar_h = 8 * s;
  for (int x = 0; x < bar_w; ++x) {
    const float t = bar_w > 1 ? static_cast<float>(x) / static_cast<float>(bar_w - 1) : 0.0f;
    image.fill_rect(bar_x + x, bar_y, 1, bar_h, heat_colour(t));
  }

  const int label_y = bar_y + bar_h + 2 * s;
  const bool clipped = range.highest > range.max;
  const std::string lo = std::to_string(range.min), hi = std::to_string(range.max) + (clipped ? "+" : "");
  const int lo_w = text_width(lo, s), hi_w = text_width(hi, s);
  draw_text(image, lo, bar_x, label_y, s, kText);
  const int hi_x = bar_x + bar_w - hi_w;
  if (hi_x > bar_x + lo_w + kGlyphAdvance * s) draw_text(image, hi, hi_x, label_y, s, kText);
  // The caption goes in the middle only when it leaves at least two glyphs of space to either label.
  const std::string most = ", MAX " + std::to_string(range.highest);
  const std::vector<std::string> captions =
      clipped ? std::vector<std::string>{caption.full + most, caption.word + most, most.substr(2), caption.word}
              : std::vector<std::string>{caption.full, caption.word};
  for (const std::string& text : captions) {
    const int w = text_width(text, s);
    const int x = bar_x + (bar_w - w) / 2;
    if (x >= bar_x + lo_w + 2 * kGlyphAdvance * s && x + w <= hi_x - 2 * kGlyphAdvance * s) {
      draw_text(image, text, x, label_y, s, kText);
      break;
    }
  }
}

CostRange shared_cost_range(std::span<const HeatFrame* const> frames) {
  std::vector<std::uint64_t> pooled;
  for (const HeatFrame* frame : frames) pooled.insert(pooled.end(), frame->cost.begin(), frame->cost.end());
  return cost_range(pooled);
}

Image draw_heat_frame(const HeatFrame& frame, const CostRange& scale, const HeatCaption& caption) {
  if (frame.cost.size() != static_cast<std::size_t>(frame.width) * static_cast<std::size_t>(frame.height) ||
      frame.brightness.size() != frame.cost.size()) {
    throw Error("heat frame: " + std::to_string(frame.cost.size()) + " costs and " +
                std::to_string(frame.brightness.size()) + " brightness values for " + std::to_string(frame.width) +
                " x " + std::to_string(frame.height) + " pixels");
  }
  Image image = Image::filled(frame.width, frame.height, Rgb{0, 0, 0});
  for (int y = 0; y < frame.height; ++y) {
    for (int x = 0; x < frame.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(frame.width) + x;
      const Rgb c = heat_colour(cost_fraction(frame.cost[i], scale));
      const float b = frame.brightness[i];
      image.set(x, y,
                {static_cast<std::uint8_t>(std::lround(c.r * b)), static_cast<std::uint8_t>(std::lround(c.g * b)),
                 static_cast<std::uint8_t>(std::lround(c.b * b))});
    }
  }
  CostRange legend = scale;
  legend.highest = frame.range.highest;
  draw_heat_legend(image, legend, caption);
  return image;
}

}  // namespace rayaccel
