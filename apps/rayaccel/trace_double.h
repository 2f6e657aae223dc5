// The double-precision half of `rayaccel trace` (--precision double, trace_double.cpp): the hook trace_command.cpp
// calls.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace rayaccel::cli {

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
