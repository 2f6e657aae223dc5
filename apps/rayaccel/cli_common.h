// Helpers every subcommand shares: usage errors, argument parsing (vectors, resolutions), thread limits, timing,
// the stderr progress line (progress.h), scene/camera/accelerator setup and JSON output.
#pragma once

#include <tbb/global_control.h>

#include <chrono>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/core/dvec3.h"
#include "rayaccel/core/error.h"
#include "rayaccel/core/output_file.h"
#include "rayaccel/scene/geometry_table.h"
#include "rayaccel/scene/scene.h"
#include "rayaccel/render/camera.h"
#include "rayaccel/render/heatmap.h"
#include "progress.h"

namespace rayaccel::cli {

/// A bad command-line value: reported on one line, exit code 2.
class UsageError : public Error {
 public:
  explicit UsageError(const std::string& message) : Error(message) {}
};

inline constexpr int kExitRuntime = 1;
inline constexpr int kExitUsage = 2;
/// `trace` builds its structure this many times (float and double scenes alike) and reports the median.
inline constexpr int kTraceBuilds = 3;

/// "x,y,z" with three finite numbers; throws UsageError naming `what` and the text otherwise.
Vec3 parse_vec3(std::string_view text, std::string_view what);
/// The same in double (each number read with one rounding to double).
DVec3 parse_dvec3(std::string_view text, std::string_view what);
/// "WxH" (or "N" for N x N) with 1 <= W, H <= 16384.
std::pair<int, int> parse_resolution(std::string_view text, std::string_view what);
/// A comma-separated list; empty items are dropped.
std::vector<std::string> split_list(std::string_view text);
/// Throws UsageError unless low <= value <= high.
void require_range(long long value, long long low, long long high, std::string_view what);

/// --heat-max, shared by render and bench: its help text, its check (1 <= value <= 2^53) and the scale it sets.
inline constexpr const char* kHeatMaxHelp =
    "Heat maps: cost (nodes + primitives per ray) at the top of the colour scale, whose bottom is then 0; costs "
    "above it get the top colour (default: render scales each image from its cheapest ray to its 99th percentile; "
    "bench puts every heat map of the run on one such scale)";
void require_heat_max(std::uint64_t value);
CostRange fixed_heat_scale(std::uint64_t max);

/// Limits TBB (and so every build and batch) to `threads` workers for its lifetime; 0 keeps TBB's default.
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  /// Workers TBB may use now.
  static int active();

 private:
  std::unique_ptr<tbb::global_control> control_;
};

/// Wall-clock milliseconds since construction.
class Stopwatch {
 public:
  double milliseconds() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

double median(std::vector<double> values);

/// True for a "builtin:..." scene spec.
bool is_builtin(std::string_view spec);
/// Loads a scene spec (file path or builtin:...); a missing file is a usage error naming it. With `geometries`, the
/// scene's meshes as load_scene() numbers them.
Scene load_scene_checked(std::string_view spec, GeometryTable* geometries = nullptr);
/// True for a "builtin:..." scene spec.
bool is_builtin(std::string_view spec);
/// Throws UsageError naming a scene file that does not exist or is not a regular file (builtin specs pass).
void check_scene_exists(std::string_view spec);
/// The MANIFEST camera of a shared scene file, else a camera framing the scene's bounds.
Camera default_camera(std::string_view spec, const Scene& scene);

/// A spec of a comparison entry of the registry (another library: "embree", "embree:quality=high,robust=1", where
/// Embree was found at build time); false for rayaccel's structures and for specs naming nothing registered.
bool is_comparison_spec(std::string_view spec);
/// Checks an accelerator spec without building; throws UsageError naming it.
void check_accelerator_spec(std::string_view spec);
/// Creates an accelerator from a spec; a structure with worker threads of its own (Embree) gets `threads` of them
/// unless the spec sets its `threads` option.
std::unique_ptr<Accelerator> make_structure(std::string_view spec, int threads);
/// The structure used when --accel is not given.
std::string default_accelerator_spec();

/// A file name made from free text: ':' ',' '=' '/' and spaces become '_'.
std::string safe_file_name(std::string_view text);

}  // namespace rayaccel::cli
