// The bench's HTML report (write_html_report, bench.h): one self-contained page with inline CSS and inline-SVG
// charts; the images are files beside it, referenced by relative path, so the page needs no network and no Python.
#include <fmt/core.h>
#include <sys/utsname.h>

#include <cctype>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "bench.h"
#include "bench_chart.h"
#include "cli_common.h"
#include "commit.h"
#include "rayaccel/render/colormap.h"
#include "rayaccel/version.h"

namespace rayaccel::cli {

namespace {

constexpr const char* kStyle = R"(
body{font:14px/1.4 system-ui,sans-serif;margin:24px;color:#222;max-width:1500px}
h1{font-size:22px;margin:0 0 4px} h2{font-size:18px;margin:28px 0 6px;border-bottom:1px solid #ccc}
h3{font-size:15px;margin:18px 0 6px} .meta{color:#555;margin:0}
.wide{overflow-x:auto} table{border-collapse:collapse;font-variant-numeric:tabular-nums;margin:6px 0}
th,td{padding:3px 8px;border-bottom:1px solid #e4e4e4;text-align:right;white-space:nowrap}
th:first-child,td:first-child{text-align:left} th{background:#f3f3f3} td small{color:#777}
tr.picked td:first-child{font-weight:600} td.bad{color:#b00020;font-weight:600}
.charts{display:flex;flex-wrap:wrap;gap:10px 28px}
svg.chart text{font:11px system-ui,sans-serif;fill:#222} svg.chart .title{font-size:13px;font-weight:600}
svg.chart .unit{font-weight:400;fill:#666} svg.chart .picked{font-weight:700} svg.chart .value{fill:#444}
.legend span{margin-right:16px;white-space:nowrap} .legend i{display:inline-block;width:12px;height:12px;
margin-right:5px;vertical-align:-1px}
.images{display:flex;flex-wrap:wrap;gap:14px}
figure{margin:0;padding:6px;border:1px solid #ddd;background:#fafafa}
figure img{width:192px;height:192px;image-rendering:pixelated;display:inline-block;margin-right:4px;background:#000}
figcaption{font-size:12px;max-width:392px;overflow-wrap:anywhere}
.ramp{display:inline-block;width:240px;height:12px;vertical-align:-2px;margin:0 6px}
)";

std::string read_first_line(const char* path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) {
      return line.substr(line.find(':') + 2);
    }
  }
  return "unknown CPU";
}

std::string machine_html() {
  utsname u{};
  const std::string os = uname(&u) == 0 ? fmt::format("{} {} {}", u.sysname, u.release, u.machine) : "unknown OS";
  const std::string load = read_first_line("/proc/loadavg");
  char when[64] = "unknown time";
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  if (gmtime_r(&now, &utc)) std::strftime(when, sizeof when, "%Y-%m-%d %H:%M UTC", &utc);
  return fmt::format(
      "<p class=\"meta\">Machine: {}, {} hardware threads, {}; load average at the end of the run: {}</p>"
      "<p class=\"meta\">rayaccel {}, commit {}; written {}</p>",
      html_escape(cpu_model()), std::thread::hardware_concurrency(), html_escape(os),
      html_escape(load.empty() ? "unknown" : load.substr(0, load.find(' ', load.find(' ', load.find(' ') + 1) + 1))),
      RAYACCEL_VERSION_STRING, html_escape(RAYACCEL_COMMIT), when);
}

std::string ratio_note(double value, double reference) {
  return reference > 0.0 ? fmt::format("{:.3g}x embree", value / reference) : "";
}

double megabytes(std::size_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }

std::string table_html(const SceneReport& report, const std::string& default_spec) {
  const StructureResult* embree = embree_row(report);
  std::string html = "<div class=\"wide\"><table><tr><th>structure</th><th>build ms</th><th>memory MB</th>"
                     "<th>with input MB</th>";
  if (!report.rows.empty()) {
    for (const auto& k : report.rows.front().kinds) {
      html += fmt::format("<th>{}<br><small>Mrays/s</small></th>", to_string(k.kind));
    }
  }
  html += "<th>mismatches</th></tr>";
  const auto cell = [&](double value, double reference, bool ratio) {
    const std::string note = ratio ? ratio_note(value, reference) : "";
    return fmt::format("<td>{}{}</td>", number(value), note.empty() ? "" : "<br><small>" + note + "</small>");
  };
  for (const auto& row : report.rows) {
    const Family family = family_of(row.spec, default_spec);
    const bool picked = family == Family::embree || family == Family::default_structure;
    html += fmt::format("<tr{}><td>{}</td>", picked ? " class=\"picked\"" : "", html_escape(row.spec));
    if (!row.failure.empty()) {
      html += fmt::format("<td class=\"bad\" colspan=\"{}\">FAILED: {}</td></tr>", 4 + row.kinds.size(),
                          html_escape(row.failure));
      continue;
    }
    const bool ratio = embree && &row != embree;
    html += cell(row.build_ms_median, embree ? embree->build_ms_median : 0.0, ratio);
    html += cell(megabytes(row.memory_bytes), embree ? megabytes(embree->memory_bytes) : 0.0, ratio);
    html += cell(megabytes(row.memory_bytes + row.input_memory_bytes),
                 embree ? megabytes(embree->memory_bytes + embree->input_memory_bytes) : 0.0, ratio);
    for (std::size_t k = 0; k < row.kinds.size(); ++k) {
      const double reference = embree && k < embree->kinds.size() ? embree->kinds[k].mrays_s_median : 0.0;
      html += cell(row.kinds[k].mrays_s_median, reference, ratio);
    }
    const bool bad = row.failed();
    html += fmt::format("<td{}>{}{}</td></tr>", bad ? " class=\"bad\"" : "", row.mismatches(),
                        row.validate_problems.empty() ? "" : fmt::format(" +{} INVALID", row.validate_problems.size()));
  }
  return html + "</table></div>";
}

std::string charts_html(const SceneReport& report, const std::string& default_spec) {
  const StructureResult* embree = embree_row(report);
  std::vector<const StructureResult*> rows;
  for (const auto& row : report.rows) {
    if (row.failure.empty()) rows.push_back(&row);
  }
  if (rows.empty()) return "";
  std::string html = "<div class=\"charts\">";
  for (std::size_t k = 0; k < rows.front()->kinds.size(); ++k) {
    std::vector<Bar> bars;
    for (const StructureResult* row : rows) {
      const double value = row->kinds[k].mrays_s_median;
      const double reference = embree && row != embree ? embree->kinds[k].mrays_s_median : 0.0;
      bars.push_back({row->spec, value, family_of(row->spec, default_spec), ratio_note(value, reference)});
    }
    html += svg_bar_chart(fmt::format("{} rays", to_string(rows.front()->kinds[k].kind)), bars, "Mrays/s");
  }
  std::vector<Bar> build, memory;
  for (const StructureResult* row : rows) {
    const Family family = family_of(row->spec, default_spec);
    const bool ratio = embree && row != embree;
    build.push_back({row->spec, row->build_ms_median, family,
                     ratio ? ratio_note(row->build_ms_median, embree->build_ms_median) : ""});
    const double total = megabytes(row->memory_bytes + row->input_memory_bytes);
    memory.push_back({row->spec, total, family,
                      ratio ? ratio_note(total, megabytes(embree->memory_bytes + embree->input_memory_bytes)) : ""});
  }
  html += svg_bar_chart("build time", build, "ms, median");
  html += svg_bar_chart("memory with input", memory, "MB");
  return html + "</div>";
}

/// A relative path as a URL path: every byte but unreserved characters and '/' percent-encoded.
std::string url_path(const std::filesystem::path& path) {
  std::string out;
  for (const unsigned char c : path.generic_string()) {
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~' || c == '/') {
      out += static_cast<char>(c);
    } else {
      out += fmt::format("%{:02X}", c);
    }
  }
  return out;
}

std::string heat_ramp_css() {
  std::string stops;
  for (int i = 0; i <= 8; ++i) {
    const Rgb c = heat_colour(static_cast<float>(i) / 8.0f);
    stops += fmt::format("{}#{:02x}{:02x}{:02x}", i ? "," : "", c.r, c.g, c.b);
  }
  return "background:linear-gradient(to right," + stops + ")";
}

std::string images_html(const SceneReport& report, const std::filesystem::path& dir,
                        const std::filesystem::path& images, const CostRange& heat) {
  std::string html;
  for (const auto& row : report.rows) {
    const std::string normals = bench_image_name(report.name, row.spec, "normals");
    const std::string heatmap = bench_image_name(report.name, row.spec, "heatmap");
    std::error_code ec;
    if (!std::filesystem::exists(dir / images / normals, ec) || !std::filesystem::exists(dir / images / heatmap, ec)) {
      continue;
    }
    html += fmt::format(
        "<figure><img src=\"{0}\" alt=\"normals of {2}\"><img src=\"{1}\" alt=\"heat map of {2}\">"
        "<figcaption>{2}: normals, heat map</figcaption></figure>",
        url_path(images / normals), url_path(images / heatmap), html_escape(row.spec));
  }
  if (html.empty()) return "";
  return fmt::format(
      "<h3>Images</h3><p>Heat maps: traversal cost per primary ray (nodes entered + primitives tested) on one scale "
      "shared by every image of the run: {}<span class=\"ramp\" style=\"{}\"></span>{}{}</p><div class=\"images\">{}"
      "</div>",
      heat.min, heat_ramp_css(), heat.max, heat.highest > heat.max ? " (dearer rays clipped to the top colour)" : "",
      html);
}

}  // namespace

void write_html_report(const std::filesystem::path& dir, const std::vector<SceneReport>& reports,
                       const std::filesystem::path& images, const CostRange& heat, const BenchArgs& args) {
  const std::string default_spec = default_accelerator_spec();
  std::string body;
  for (const auto& report : reports) {
    body += fmt::format(
        "<h2>{}</h2><p class=\"meta\">{} {}, {} threads, {}x{} camera rays, reference: {}; build times of "
        "rayaccel's structures include the scene preparation ({:.2f} ms)</p>",
        html_escape(report.name), report.primitives, html_escape(report.kind), report.threads, report.resolution,
        report.resolution, html_escape(report.reference), report.scene_preparation_ms);
    body += table_html(report, default_spec);
    body += charts_html(report, default_spec);
    body += images_html(report, dir, images, heat);
  }
  std::string command = "rayaccel bench";
  for (const auto& scene : args.scenes) command += " " + scene;
  if (!args.accel.empty()) command += " --accel " + args.accel;
  if (!args.compare.empty()) command += " --compare " + args.compare;
  command += fmt::format(" --res {} --repeat {}", args.resolution, args.repeat);
  const std::string page = fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>rayaccel bench</title>"
      "<style>{}</style></head><body><h1>rayaccel bench</h1><p class=\"meta\"><code>{}</code></p>{}"
      "<p>Bars: median Mrays/s of the timed passes (longer is faster), build time and memory (shorter is better); "
      "every answer was checked against the reference before timing.</p>{}{}</body></html>\n",
      kStyle, html_escape(command), machine_html(), family_legend_html(), body);
  write_file_atomically(dir / "index.html", page, "report");
}

}  // namespace rayaccel::cli
