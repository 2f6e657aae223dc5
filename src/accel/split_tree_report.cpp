// Build statistics and validation checks shared by the kd-tree and the BSP tree.
#include "rayaccel/accel/split_tree_report.h"

namespace rayaccel {

std::vector<BuildStatistic> split_tree_statistics(const SplitTreeCounts& c, const Scene* scene) {
  const std::size_t prims = scene ? scene->valid_count() : 0;
  return {{"nodes", double(c.nodes)},
          {"leaves", double(c.leaves)},
          {"empty_leaves", double(c.empty_leaves)},
          {"max_depth", double(c.max_depth)},
          {"references_per_primitive", prims ? double(c.references) / double(prims) : 0.0},
          {"sah_cost", c.sah_cost},
          {"build_ms", c.build_ms}};
}

void report_unreached(const std::vector<std::uint8_t>& reached_nodes, const std::vector<std::uint8_t>& referenced,
                      const Scene& scene, ProblemList& report) {
  for (std::size_t i = 0; i < reached_nodes.size(); ++i) {
    if (!reached_nodes[i]) {
      report("node " + std::to_string(i) + " is unreachable");
      break;
    }
  }
  report_unreferenced(scene, referenced, "leaf", report.problems);
}

}  // namespace rayaccel
