// What several structures' validate() share, written once: the cap on reported problems and the check that every
// valid primitive of the scene is referenced somewhere (a leaf, a cell), so that no ray can miss it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rayaccel/scene/scene.h"

namespace rayaccel {

/// validate() reports at most this many problems: enough to see a pattern, few enough to read.
inline constexpr std::size_t kMaxProblems = 20;

/// A problem list that keeps the first kMaxProblems problems.
struct ProblemList {
  std::vector<std::string> problems;
  void operator()(const std::string& problem) {
    if (problems.size() < kMaxProblems) problems.push_back(problem);
  }
};

/// Adds "valid primitive N is in no <place>" for each valid primitive of `scene` that `referenced` (one entry per
/// primitive id) leaves at 0, while `problems` holds fewer than kMaxProblems.
inline void report_unreferenced(const Scene& scene, std::span<const std::uint8_t> referenced, std::string_view place,
                                std::vector<std::string>& problems) {
  for (std::uint32_t id = 0; id < referenced.size() && problems.size() < kMaxProblems; ++id) {
    if (scene.is_valid(id) && !referenced[id]) {
      problems.push_back("valid primitive " + std::to_string(id) + " is in no " + std::string(place));
    }
  }
}

}  // namespace rayaccel
