// Shared command-line helpers (see cli_common.h).
#include "cli_common.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <utility>

#include "rayaccel/accel/default_spec.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/core/number_text.h"
#include "rayaccel/render/image_limits.h"
#include "rayaccel/scene/import.h"

namespace rayaccel::cli {

namespace {

/// A finite number of type Real (float or double), spaces around it allowed.
template <class Real>
bool parse_finite(std::string_view text, Real& out) {
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
  const auto v = parse_real(text);
  if (!v || !std::isfinite(static_cast<Real>(*v))) return false;
  out = static_cast<Real>(*v);
  return true;
}

bool parse_int(std::string_view text, int& out) {
  const auto v = parse_integer(text);
  if (!v || !std::in_range<int>(*v)) return false;
  out = static_cast<int>(*v);
  return true;
}

}  // namespace

namespace {

/// "x,y,z" as three finite numbers of V's precision; throws UsageError naming `what` and the text otherwise.
template <class V>
V parse_three(std::string_view text, std::string_view what) {
  const auto parts = split_list(text);
  V v;
  const bool ok = parts.size() == 3 && std::count(text.begin(), text.end(), ',') == 2 &&
                  parse_finite(parts[0], v.x) && parse_finite(parts[1], v.y) && parse_finite(parts[2], v.z);
  if (!ok) {
    throw UsageError(std::string(what) + ": '" + std::string(text) + "' is not three finite numbers x,y,z");
  }
  return v;
}

}  // namespace

Vec3 parse_vec3(std::string_view text, std::string_view what) { return parse_three<Vec3>(text, what); }

DVec3 parse_dvec3(std::string_view text, std::string_view what) { return parse_three<DVec3>(text, what); }

std::pair<int, int> parse_resolution(std::string_view text, std::string_view what) {
  const auto x = text.find_first_of("xX");
  int w = 0, h = 0;
  const bool ok = x == std::string_view::npos ? (parse_int(text, w) && (h = w, true))
                                              : (parse_int(text.substr(0, x), w) && parse_int(text.substr(x + 1), h));
  if (!ok || w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide) {
    throw UsageError(std::string(what) + ": '" + std::string(text) + "' is not a resolution WxH with 1 <= W, H <= " +
                     std::to_string(kMaxImageSide));
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

bool is_builtin(std::string_view spec) { return spec.rfind("builtin:", 0) == 0; }

void check_scene_exists(std::string_view spec) {
  if (!is_builtin(spec)) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(std::filesystem::path(spec), ec)) {
      throw UsageError("scene file '" + std::string(spec) + "' does not exist (or is not a file)");
    }
  }
}

Scene load_scene_checked(std::string_view spec, GeometryTable* geometries) {
  check_scene_exists(spec);
  return load_scene(spec, geometries);
}

Camera default_camera(std::string_view spec, const Scene& scene) {
  if (!is_builtin(spec)) {
    if (auto camera = standard_camera(std::filesystem::path(spec))) return *camera;
  }
  const AABB box = scene.bounds().is_empty() ? AABB(Vec3{-1.0f}, Vec3{1.0f}) : scene.bounds();
  return Camera::framing(box);
}

bool is_comparison_spec(std::string_view spec) {
  try {
    return find_accelerator(parse_accelerator_spec(spec).name).comparison;
  } catch (const Error&) {
    return false;
  }
}

void check_accelerator_spec(std::string_view spec) {
  try {
    make_accelerator(spec);  // parses, resolves options and runs the structure's own checks; builds nothing
  } catch (const Error& e) {
    throw UsageError(std::string("--accel: ") + e.what());
  }
}

std::unique_ptr<Accelerator> make_structure(std::string_view spec, int threads) {
  return make_accelerator(spec, {{"threads", std::to_string(threads)}});
}

std::string default_accelerator_spec() { return rayaccel::default_accelerator_spec(); }

std::string safe_file_name(std::string_view text) {
  std::string out(text);
  for (char& c : out) {
    if (c == ':' || c == ',' || c == '=' || c == '/' || c == '\\' || c == ' ') c = '_';
  }
  return out;
}

}  // namespace rayaccel::cli
