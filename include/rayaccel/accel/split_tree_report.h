// Reporting shared by the split-plane trees (kd-tree, BSP tree): the build statistics both publish, and the closing
// checks of their validate() walks (every node reached, every valid primitive in some leaf).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/validation_report.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {

struct SplitTreeCounts {
  std::size_t nodes = 0;
  std::size_t leaves = 0;
  std::size_t empty_leaves = 0;
  int max_depth = 0;
  std::size_t references = 0;  ///< entries of the leaves' primitive-index array
  double sah_cost = 0.0;
  double build_ms = 0.0;
};

/// The build statistics of a split-plane tree; references per primitive are over the scene's valid primitives.
std::vector<BuildStatistic> split_tree_statistics(const SplitTreeCounts& counts, const Scene* scene);

/// Collects validate() problems, keeping the first 20.

/// Reports the first node never reached and every valid primitive no leaf referenced.
void report_unreached(const std::vector<std::uint8_t>& reached_nodes, const std::vector<std::uint8_t>& referenced,
                      const Scene& scene, ProblemList& report);

}  // namespace rayaccel
