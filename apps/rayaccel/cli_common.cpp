// Shared command-line helpers (see cli_common.h).
#include "cli_common.h"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "rayaccel/accel/registry.h"
#include "rayaccel/compare/embree_accelerator.h"
#include "rayaccel/scene/import.h"

namespace rayaccel::cli {

namespace {

bool parse_float(std::string_view text, float& out) {
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
  if (text.empty()) return false;
  const std::string s(text);
  std::size_t used = 0;
  try {
    out = std::stof(s, &used);
  } catch (const std::exception&) {
    return false;
  }
  return used == s.size() && std::isfinite(out);
}

bool parse_int(std::string_view text, int& out) {
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return ec == std::errc() && ptr == end && !text.empty();
}

}  // namespace

Vec3 parse_vec3(std::string_view text, std::string_view what) {
  const auto parts = split_list(text);
  Vec3 v;
  const bool ok = parts.size() == 3 && std::count(text.begin(), text.end(), ',') == 2 && parse_float(parts[0], v.x) &&
                  parse_float(parts[1], v.y) && parse_float(parts[2], v.z);
  if (!ok) {
    throw UsageError(std::string(what) + ": '" + std::string(text) + "' is not three finite numbers x,y,z");
  }
  return v;
}

std::pair<int, int> parse_resolution(std::string_view text, std::string_view what) {
  const auto x = text.find_first_of("xX");
  int w = 0, h = 0;
  const bool ok = x == std::string_view::npos ? (parse_int(text, w) && (h = w, true))
                                              : (parse_int(text.substr(0, x), w) && parse_int(text.substr(x + 1), h));
  constexpr int kMax = 16384;
  if (!ok || w < 1 || h < 1 || w > kMax || h > kMax) {
    throw UsageError(std::string(what) + ": '" + std::string(text) + "' is not a resolution WxH with 1 <= W, H <= " +
                     std::to_string(kMax));
  }
  return {w, h};
}

std::vector<std::string> split_list(std::string_view text) {
  std::vector<std::string> out;
  while (true) {
    const auto comma = text.find(',');
    std::string_view item = text.substr(0, comma);
    while (!item.empty() && item.front() == ' ') item.remove_prefix(1);
    while (!item.empty() && item.back() == ' ') item.remove_suffix(1);
    if (!item.empty()) out.emplace_back(item);
    if (comma == std::string_view::npos) break;
    text.remove_prefix(comma + 1);
  }
  return out;
}

void require_range(long long value, long long low, long long high, std::string_view what) {
  if (value < low || value > high) {
    throw UsageError(std::string(what) + ": " + std::to_string(value) + " is out of range [" + std::to_string(low) +
                     ", " + std::to_string(high) + "]");
  }
}

void require_heat_max(std::uint64_t value) {
  constexpr std::uint64_t kLargest = std::uint64_t{1} << 53;  // costs are compared as doubles
  if (value < 1 || value > kLargest) {
    throw UsageError("--heat-max: " + std::to_string(value) + " is out of range [1, " + std::to_string(kLargest) + "]");
  }
}

CostRange fixed_heat_scale(std::uint64_t max) { return CostRange{0, max, max}; }

ThreadLimit::ThreadLimit(int threads) {
  if (threads > 0) {
    control_ = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                     static_cast<std::size_t>(threads));
  }
}

int ThreadLimit::active() {
  return static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

void Progress::stage(const std::string& label) {
  done();
  label_ = label;
  step_.clear();
  last_percent_ = -1;
  open_ = true;
  if (isatty(fileno(stderr))) {
    redraw();
  } else {
    std::cerr << label_ << "\n";
  }
}

void Progress::step(const std::string& label) {
  step_ = label;
  last_percent_ = -1;
  if (open_ && isatty(fileno(stderr))) redraw();
}

void Progress::update(float fraction) {
  if (!open_ || !isatty(fileno(stderr))) return;
  const int percent = static_cast<int>(std::clamp(fraction, 0.0f, 1.0f) * 100.0f);
  if (percent == last_percent_) return;
  last_percent_ = percent;
  redraw();
}

void Progress::redraw() const {
  std::cerr << "\r\033[K" << label_;
  if (!step_.empty()) std::cerr << ": " << step_;
  if (last_percent_ >= 0) std::cerr << " " << last_percent_ << "%";
  std::cerr << std::flush;
}

void Progress::done() {
  if (open_ && isatty(fileno(stderr))) std::cerr << "\r\033[K" << std::flush;
  open_ = false;
}

namespace {
bool is_builtin(std::string_view spec) { return spec.rfind("builtin:", 0) == 0; }
}  // namespace

Scene load_scene_checked(std::string_view spec) {
  if (!is_builtin(spec)) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(std::filesystem::path(spec), ec)) {
      throw UsageError("scene file '" + std::string(spec) + "' does not exist (or is not a file)");
    }
  }
  return load_scene(spec);
}

Camera default_camera(std::string_view spec, const Scene& scene) {
  if (!is_builtin(spec)) {
    if (auto camera = standard_camera(std::filesystem::path(spec))) return *camera;
  }
  const AABB box = scene.bounds().is_empty() ? AABB(Vec3{-1.0f}, Vec3{1.0f}) : scene.bounds();
  return Camera::framing(box);
}

bool is_embree_spec(std::string_view spec) { return spec == "embree" || spec.starts_with("embree:"); }

#ifdef RAYACCEL_HAVE_EMBREE
namespace {

/// "embree" or "embree:quality=low|medium|high,robust=0|1": Embree's build quality and RTC_SCENE_FLAG_ROBUST.
EmbreeOptions parse_embree_spec(std::string_view spec) {
  EmbreeOptions options;
  if (spec == "embree") return options;
  for (const std::string& item : split_list(spec.substr(std::string_view("embree:").size()))) {
    const std::size_t eq = item.find('=');
    const std::string key = item.substr(0, eq), value = eq == std::string::npos ? "" : item.substr(eq + 1);
    if (key == "quality" && (value == "low" || value == "medium" || value == "high")) {
      options.quality = value == "low"      ? EmbreeBuildQuality::low
                        : value == "medium" ? EmbreeBuildQuality::medium
                                            : EmbreeBuildQuality::high;
    } else if (key == "robust" && (value == "0" || value == "1" || value == "true" || value == "false")) {
      options.robust = value == "1" || value == "true";
    } else {
      throw UsageError("--accel: '" + item + "' in '" + std::string(spec) +
                       "' is not an Embree option (known: quality=low|medium|high, robust=0|1)");
    }
  }
  return options;
}

}  // namespace
#endif

void check_accelerator_spec(std::string_view spec) {
#ifdef RAYACCEL_HAVE_EMBREE
  if (is_embree_spec(spec)) {
    parse_embree_spec(spec);
    return;
  }
#endif
  try {
    make_accelerator(spec);  // parses, resolves options and runs the structure's own checks; builds nothing
  } catch (const UsageError&) {
    throw;
  } catch (const Error& e) {
    throw UsageError(std::string("--accel: ") + e.what());
  }
}

std::unique_ptr<Accelerator> make_structure(std::string_view spec, int threads) {
#ifdef RAYACCEL_HAVE_EMBREE
  if (is_embree_spec(spec)) {
    EmbreeOptions options = parse_embree_spec(spec);
    options.threads = threads;
    auto embree = std::make_unique<EmbreeAccelerator>(options);
    embree->set_spec(std::string(spec));
    return embree;
  }
#endif
  (void)threads;
  return make_accelerator(spec);
}

std::string default_accelerator_spec() {
  const auto& registry = accelerator_registry();
  // The fastest structure first (the wide SIMD BVH), then the binary BVH.
  for (const char* preferred : {"bvh_wide", "bvh"}) {
    for (const auto& info : registry) {
      if (info.name == preferred) return info.name;
    }
  }
  for (const auto& info : registry) {
    if (info.name != "brute_force") return info.name;
  }
  return "brute_force";
}

std::string safe_file_name(std::string_view text) {
  std::string out(text);
  for (char& c : out) {
    if (c == ':' || c == ',' || c == '=' || c == '/' || c == '\\' || c == ' ') c = '_';
  }
  return out;
}

}  // namespace rayaccel::cli
