// Inline-SVG bar charts of the bench report (see bench_chart.h): plain SVG elements, no script, no fonts to fetch.
#include "bench_chart.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace rayaccel::cli {

namespace {

constexpr int kLabelWidth = 210;  // px of structure names left of the bars
constexpr int kBarWidth = 230;    // px of the longest bar
constexpr int kValueWidth = 160;  // px of value text right of the bars
constexpr int kRowHeight = 17;
constexpr int kTitleHeight = 24;
constexpr std::size_t kLabelChars = 32;  // longer specs are shortened, the full one in a tooltip

struct FamilyStyle {
  Family family;
  const char* colour;
  const char* name;
};
constexpr FamilyStyle kStyles[] = {
    {Family::embree, "#d95f02", "Embree (comparison)"},
    {Family::default_structure, "#1b4f9c", "default structure"},
    {Family::bvh, "#7fa7d6", "BVH family"},
    {Family::spatial, "#5aa469", "spatial subdivisions (grids, k-d tree, octree, BSP)"},
    {Family::brute_force, "#9a9a9a", "brute force"},
};

const FamilyStyle& style(Family family) {
  for (const auto& s : kStyles) {
    if (s.family == family) return s;
  }
  return kStyles[2];
}

std::string short_label(const std::string& label) {
  return label.size() <= kLabelChars ? label : label.substr(0, kLabelChars - 3) + "...";
}

std::string short_number(double value) {
  if (value == 0.0) return "0";
  return std::abs(value) < 1.0 ? fmt::format("{:.3g}", value) : fmt::format("{:.4g}", value);
}

}  // namespace

Family family_of(const std::string& spec, const std::string& default_spec) {
  const std::string name = spec.substr(0, spec.find(':'));
  if (name == "embree") return Family::embree;
  if (spec == default_spec) return Family::default_structure;
  if (name == "brute_force") return Family::brute_force;
  if (name.rfind("bvh", 0) == 0) return Family::bvh;
  return Family::spatial;
}

std::string html_escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string svg_bar_chart(const std::string& title, std::vector<Bar> bars, const std::string& unit) {
  std::stable_sort(bars.begin(), bars.end(), [](const Bar& a, const Bar& b) { return a.family < b.family; });
  double top = 0.0;
  for (const auto& bar : bars) {
    if (std::isfinite(bar.value)) top = std::max(top, bar.value);
  }
  const int width = kLabelWidth + kBarWidth + kValueWidth;
  const int height = kTitleHeight + kRowHeight * static_cast<int>(bars.size()) + 6;
  std::string svg = fmt::format(
      "<svg class=\"chart\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" role=\"img\" aria-label=\"{2}\">"
      "<text x=\"0\" y=\"15\" class=\"title\">{2} <tspan class=\"unit\">({3})</tspan></text>",
      width, height, html_escape(title), html_escape(unit));
  for (std::size_t i = 0; i < bars.size(); ++i) {
    const Bar& bar = bars[i];
    const FamilyStyle& s = style(bar.family);
    const int y = kTitleHeight + kRowHeight * static_cast<int>(i);
    const double fraction = top > 0.0 && std::isfinite(bar.value) ? std::max(bar.value, 0.0) / top : 0.0;
    const int length = std::max(1, static_cast<int>(std::lround(fraction * kBarWidth)));
    const bool picked = bar.family == Family::embree || bar.family == Family::default_structure;
    svg += fmt::format(
        "<g><title>{0}: {1} {2}{3}</title>"
        "<text x=\"{4}\" y=\"{5}\" text-anchor=\"end\" class=\"{6}\">{7}</text>"
        "<rect x=\"{8}\" y=\"{9}\" width=\"{10}\" height=\"{11}\" fill=\"{12}\"/>"
        "<text x=\"{13}\" y=\"{5}\" class=\"value\">{1}{14}</text></g>",
        html_escape(bar.label), short_number(bar.value), html_escape(unit),
        bar.note.empty() ? "" : ", " + html_escape(bar.note), kLabelWidth - 6, y + 12, picked ? "label picked" : "label",
        html_escape(short_label(bar.label)), kLabelWidth, y + 2, length, kRowHeight - 4, s.colour,
        kLabelWidth + length + 4, bar.note.empty() ? "" : " (" + html_escape(bar.note) + ")");
  }
  return svg + "</svg>";
}

std::string family_legend_html() {
  std::string html = "<p class=\"legend\">";
  for (const auto& s : kStyles) {
    html += fmt::format("<span><i style=\"background:{}\"></i>{}</span>", s.colour, s.name);
  }
  return html + "</p>";
}

}  // namespace rayaccel::cli
