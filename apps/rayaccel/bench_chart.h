// Bar charts of a bench run as inline SVG for the HTML report: one panel per figure (a ray kind's Mrays/s, build
// time, memory), a bar per structure, coloured by family with the default structure and Embree picked out.
#pragma once

#include <string>
#include <vector>

namespace rayaccel::cli {

/// Which family a structure belongs to: its colour in the charts and its place in their order.
enum class Family { embree, default_structure, bvh, spatial, brute_force };
Family family_of(const std::string& spec, const std::string& default_spec);

struct Bar {
  std::string label;
  double value = 0.0;
  Family family = Family::bvh;
  std::string note;  ///< printed after the value, e.g. "1.05x embree"
};

/// One panel: a title, the bars sorted by family (stable within one), a linear axis from 0 to the largest value.
std::string svg_bar_chart(const std::string& title, std::vector<Bar> bars, const std::string& unit);
/// The legend of the families' colours as HTML.
std::string family_legend_html();
/// Escapes & < > " ' for HTML text and attributes.
std::string html_escape(const std::string& text);

}  // namespace rayaccel::cli
