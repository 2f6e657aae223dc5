// Output of `rayaccel bench`: aligned tables per scene (ratios to Embree when it was measured) and JSON.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "bench.h"

namespace rayaccel::cli {

const char* to_string(RayKind kind) {
  switch (kind) {
    case RayKind::primary: return "primary";
    case RayKind::diffuse: return "diffuse";
    case RayKind::shadow: return "shadow";
    case RayKind::occlusion: return "occlusion";
    case RayKind::light: return "light";
    case RayKind::packet: return "packet";
    case RayKind::light_packet: return "light_packet";
    case RayKind::diffuse_skip: return "diffuse_skip";
    case RayKind::shadow_skip: return "shadow_skip";
    case RayKind::occlusion_skip: return "occlusion_skip";
    case RayKind::light_skip: return "light_skip";
    case RayKind::beam: return "beam";
  }
  return "?";
}

std::size_t StructureResult::mismatches() const {
  std::size_t n = 0;
  for (const auto& k : kinds) n += k.mismatches;
  return n;
}

const StructureResult* embree_row(const SceneReport& report) {
  for (const auto& row : report.rows) {
    if (row.is_embree && (row.spec == "embree" || row.spec == kEmbreeWithFilter) && row.failure.empty()) return &row;
  }
  return nullptr;
}

std::string number(double value) {
  return value != 0.0 && std::abs(value) < 1.0 ? fmt::format("{:.3g}", value) : fmt::format("{:.2f}", value);
}

namespace {

/// " (ratio x)", three significant digits, or " (<0.01x)" below a hundredth (brute force), which keeps columns narrow.
std::string ratio_text(double ratio) {
  return ratio < 0.01 ? std::string(" (<0.01x)") : fmt::format(" ({:.3g}x)", ratio);
}

/// "value" or "value (ratio x)" where ratio = value / reference.
std::string with_ratio(double value, const double* reference) {
  std::string text = number(value);
  if (reference && *reference > 0.0) text += ratio_text(value / *reference);
  return text;
}

void print_aligned(const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> widths;
  for (const auto& row : rows) {
    widths.resize(std::max(widths.size(), row.size()), 0);
    for (std::size_t c = 0; c < row.size(); ++c) widths[c] = std::max(widths[c], row[c].size());
  }
  for (std::size_t r = 0; r < rows.size(); ++r) {
    std::string line;
    for (std::size_t c = 0; c < rows[r].size(); ++c) {
      if (c == 0) {
        line += fmt::format("{:<{}}", rows[r][c], widths[c]);
      } else {
        line += fmt::format("  {:>{}}", rows[r][c], widths[c]);
      }
    }
    fmt::print("{}\n", line);
    if (r == 0) fmt::print("{}\n", std::string(line.size(), '-'));
  }
}

}  // namespace

void print_table(const SceneReport& report) {
  const StructureResult* embree = embree_row(report);
  fmt::print("\nScene {} ({} {}, {} threads, {}x{} camera rays)\nreference: {}\n", report.name, report.primitives,
             report.kind, report.threads, report.resolution, report.resolution, report.reference);
  fmt::print("(build ms of rayaccel's structures includes the scene preparation, {:.2f} ms{})\n",
             report.scene_preparation_ms,
             embree ? ";\n Embree does the same work inside its build, and is measured before and after the structures, "
                      "its samples pooled"
                    : "");
  if (embree) fmt::print("(ratios in parentheses: this structure / embree)\n");
  const std::vector<KindResult> no_kinds;
  const std::vector<KindResult>& kinds = report.rows.empty() ? no_kinds : report.rows.front().kinds;
  // Three narrow tables rather than one wide one: build and memory, speed per ray kind, traversal cost per ray kind.
  std::vector<std::vector<std::string>> build = {
      {"structure", "build ms", "memory MB", "B/prim", "with input MB", "mismatches"}};
  std::vector<std::vector<std::string>> speed = {{"Mrays/s"}};
  std::vector<std::vector<std::string>> cost = {{"nodes/prims per ray"}};
  for (const auto& k : kinds) {
    speed.front().push_back(to_string(k.kind));
    // Packet traversals take no statistics, so packet rays have no nodes/prims column.
    if (!is_packet_kind(k.kind)) cost.front().push_back(to_string(k.kind));
  }
  for (const auto& row : report.rows) {
    if (!row.failure.empty()) {
      build.push_back({row.spec, "FAILED: " + row.failure});
      continue;
    }
    const bool ratio = embree && &row != embree;
    const double embree_build = embree ? embree->build_ms_median : 0.0;
    const double embree_memory = embree ? static_cast<double>(embree->memory_bytes) : 0.0;
    const double embree_total = embree ? static_cast<double>(embree->memory_bytes + embree->input_memory_bytes) : 0.0;
    const double memory = static_cast<double>(row.memory_bytes);
    const double total = static_cast<double>(row.memory_bytes + row.input_memory_bytes);
    const auto megabytes = [&](double bytes, double embree_bytes) {
      return number(bytes / (1024.0 * 1024.0)) +
             (ratio && embree_bytes > 0.0 ? ratio_text(bytes / embree_bytes) : "");
    };
    std::size_t foreign = 0, sampled = 0;
    for (const auto& k : row.kinds) {
      foreign += k.foreign_differences;
      sampled += k.checked;
    }
    // Embree's row: rays of the brute-force sample where it breaks the foreign-kernel rule (reported, not failed).
    std::string verdict = row.is_embree ? fmt::format("{} of {} sampled differ", foreign, sampled)
                                        : fmt::format("{}", row.mismatches());
    if (!row.validate_problems.empty()) verdict += fmt::format(" +{} INVALID", row.validate_problems.size());
    if (row.mismatches() > 0) verdict += " MISMATCH";
    build.push_back({row.spec, with_ratio(row.build_ms_median, ratio ? &embree_build : nullptr),
                     megabytes(memory, embree_memory),
                     fmt::format("{:.1f}", report.primitives ? memory / report.primitives : 0.0),
                     megabytes(total, embree_total), verdict});
    std::vector<std::string> speeds = {row.spec};
    std::vector<std::string> costs = {row.spec};
    for (std::size_t k = 0; k < row.kinds.size(); ++k) {
      const double* reference = ratio && k < embree->kinds.size() ? &embree->kinds[k].mrays_s_median : nullptr;
      speeds.push_back(with_ratio(row.kinds[k].mrays_s_median, reference));
      if (is_packet_kind(row.kinds[k].kind)) continue;
      costs.push_back(row.kinds[k].nodes_per_ray < 0.0
                          ? std::string("n/a")
                          : fmt::format("{:.1f}/{:.1f}", row.kinds[k].nodes_per_ray, row.kinds[k].prims_per_ray));
    }
    speed.push_back(speeds);
    cost.push_back(costs);
  }
  print_aligned(build);
  if (speed.size() > 1 && speed.front().size() > 1) {
    fmt::print("\n");
    print_aligned(speed);
  }
  if (cost.size() > 1 && cost.front().size() > 1) {
    fmt::print("\n");
    print_aligned(cost);
  }
  for (const auto& row : report.rows) {
    if (row.build_statistics.empty() || row.is_embree) continue;
    std::string line;
    for (const auto& s : row.build_statistics) line += fmt::format("{}{}={:.4g}", line.empty() ? "" : ", ", s.name, s.value);
    fmt::print("  {}: {}\n", row.spec, line);
  }
  std::size_t differences = 0;
  for (const auto& row : report.rows) {
    for (const auto& k : row.kinds) differences += k.reference_differences;
  }
  if (differences > 0) {
    fmt::print("note: on {} ray(s) Embree's triangle test disagreed with ours; brute force confirmed the structures\n",
               differences);
  }
}

nlohmann::json to_json(const SceneReport& report) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& row : report.rows) {
    nlohmann::json kinds = nlohmann::json::object();
    for (const auto& k : row.kinds) {
      nlohmann::json kind = {{"rays", k.rays},
                             {"trace_ms", k.trace_ms},
                             {"mrays_s_median", k.mrays_s_median},
                             {"checked", k.checked},
                             {"mismatches", k.mismatches},
                             {"reference_differences", k.reference_differences},
                             {"foreign_differences", k.foreign_differences}};
      if (k.nodes_per_ray >= 0.0) {
        kind["nodes_per_ray"] = k.nodes_per_ray;
        kind["primitives_tested_per_ray"] = k.prims_per_ray;
      }
      kinds[to_string(k.kind)] = kind;
    }
    nlohmann::json statistics = nlohmann::json::object();
    for (const auto& s : row.build_statistics) statistics[s.name] = s.value;
    nlohmann::json entry = {{"accel", row.spec},
                            {"is_embree", row.is_embree},
                            {"build_ms", row.build_ms},
                            {"build_ms_median", row.build_ms_median},
                            {"memory_bytes", row.memory_bytes},
                            {"input_memory_bytes", row.input_memory_bytes},
                            {"bytes_per_primitive",
                             report.primitives ? static_cast<double>(row.memory_bytes) / report.primitives : 0.0},
                            {"build_statistics", statistics},
                            {"validate_problems", row.validate_problems},
                            {"mismatches", row.mismatches()},
                            {"rays", kinds}};
    if (!row.failure.empty()) entry["failure"] = row.failure;
    rows.push_back(entry);
  }
  return {{"scene", report.name},       {"spec", report.spec},       {"kind", report.kind},
          {"primitives", report.primitives}, {"threads", report.threads}, {"resolution", report.resolution},
          {"reference", report.reference},   {"scene_preparation_ms", report.scene_preparation_ms},
          {"results", rows}};
}

}  // namespace rayaccel::cli
