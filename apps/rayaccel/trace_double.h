// The double-precision half of `rayaccel trace` (--precision double, trace_double.cpp), the hook trace_command.cpp
// calls, and the JSON summary line both halves print (trace_summary(), defined in trace_command.cpp).
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace rayaccel::cli {

/// What a trace run measured and produced, for its summary line.
struct TraceFigures {
  std::string accel;  ///< the structure's spec
  std::string scene;  ///< the scene's name
  std::size_t primitives = 0;
  std::size_t rays = 0;
  std::string query;  ///< "intersect", "occluded" or "intersect_packets"
  std::vector<double> trace_ms;
  std::size_t hit_count = 0;
  std::size_t memory_bytes = 0;
  std::size_t scene_memory_bytes = 0;
  std::size_t input_memory_bytes = 0;
};
/// The keys every trace summary has (accel, scene, primitives, rays, query, threads, trace_ms[_median],
/// mrays_s_median, hit_count, the memory figures); callers add their build, load and output keys.
nlohmann::json trace_summary(const TraceFigures& figures);

/// `trace --precision double`: the options that apply to it (trace_command.cpp refuses the others).
struct TraceDoubleArgs {
  std::string scene;
  std::string rays;    ///< a .rays64 file
  std::string accel;   ///< empty: "bvh"
  std::string offset;  ///< "x,y,z" added to every vertex in double, or empty
  std::string out;     ///< .hits64 (or .occ with occlusion), or empty
  bool occlusion = false;
  int repeat = 5;
};
/// Builds the double structure three times (median build time), traces the rays `repeat` times, writes the output
/// and prints the summary line with "precision":"double". Throws UsageError for a structure without a double
/// version or a bad --offset, Error for bad files. Runs under the caller's thread limit.
int run_trace_double(const TraceDoubleArgs& args);

}  // namespace rayaccel::cli
