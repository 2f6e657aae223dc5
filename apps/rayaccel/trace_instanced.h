// `rayaccel trace SCENE RAYS --instances`: the two-level trace (instance/instanced_accelerator.h), reached from the
// trace command (trace_command.cpp) when --instances is given.
#pragma once

#include <string>
#include <vector>

namespace rayaccel::cli {

struct InstancedTraceArgs {
  std::string scene;                    ///< read with its node hierarchy (import_instanced_scene())
  std::vector<std::string> geometries;  ///< --geometry: more scene specs, each one geometry placed with the identity
  std::string rays;
  std::string bottom;  ///< --accel: every bottom level's spec; empty for the default
  bool occlusion = false;
  int threads = 0;
  int repeat = 5;
  std::string out;  ///< .ihits (or .occ with --occlusion)
  std::string top;  ///< --top: the top level (InstancedAcceleratorOptions::top); empty for the default
};

/// Builds the two-level structure once, traces R times (median time), writes the output and prints the JSON summary.
int run_trace_instanced(const InstancedTraceArgs& args, bool threads_given);

}  // namespace rayaccel::cli
