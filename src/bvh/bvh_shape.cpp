// The builder dispatch of Bvh<BV> (one table from BvhBuilder to builder) and the configuration check.
#include <string>

#include "rayaccel/bvh/binned_sah_builder.h"
#include "rayaccel/bvh/bvh.h"
#include "rayaccel/bvh/lbvh_builder.h"
#include "rayaccel/bvh/ploc_builder.h"
#include "rayaccel/bvh/sbvh_builder.h"
#include "rayaccel/bvh/sweep_sah_builder.h"
#include "rayaccel/core/error.h"

namespace rayaccel {

const char* to_string(BvhBuilder builder) {
  switch (builder) {
    case BvhBuilder::binned: return "binned";
    case BvhBuilder::sweep: return "sweep";
    case BvhBuilder::sbvh: return "sbvh";
    case BvhBuilder::lbvh: return "lbvh";
    case BvhBuilder::ploc: return "ploc";
  }
  return "?";
}

void check_config(const BvhConfig& c) {
  if (c.max_leaf_size < 1 || c.max_leaf_size > 255) {
    throw Error("bvh: leaf_size " + std::to_string(c.max_leaf_size) + " is outside 1..255");
  }
  if (!(c.costs.traversal >= 0.0f) || !(c.costs.intersection > 0.0f)) {
    throw Error("bvh: SAH costs must be traversal >= 0 and intersection > 0 (got " +
                std::to_string(c.costs.traversal) + ", " + std::to_string(c.costs.intersection) + ")");
  }
  if (c.bin_count < 2 || c.bin_count > 64) {
    throw Error("bvh: bins " + std::to_string(c.bin_count) + " is outside 2..64");
  }
  if (!(c.max_growth >= 1.0f && c.max_growth <= 16.0f)) {
    throw Error("bvh: max_growth " + std::to_string(c.max_growth) + " is outside 1..16");
  }
  if (!(c.overlap_alpha >= 0.0f)) throw Error("bvh: overlap_alpha " + std::to_string(c.overlap_alpha) + " is < 0");
  if (c.ploc_radius < 1 || c.ploc_radius > 256) {
    throw Error("bvh: ploc_radius " + std::to_string(c.ploc_radius) + " is outside 1..256");
  }
}

BuildTree build_bvh_shape(const Scene& scene, const BvhConfig& c) {
  switch (c.builder) {
    case BvhBuilder::binned:
      return build_binned_sah(scene.build_references(),
                              {c.max_leaf_size, c.costs, c.bin_count, c.parallel_threshold});
    case BvhBuilder::sweep:
      return build_sweep_sah(scene.build_references(), {c.max_leaf_size, c.costs, c.parallel_threshold});
    case BvhBuilder::sbvh:
      return build_sbvh(scene, {c.max_leaf_size, c.costs, c.bin_count, c.max_growth, c.overlap_alpha});
    case BvhBuilder::lbvh:
      return build_lbvh(scene.build_references(), {c.max_leaf_size, c.parallel_threshold});
    case BvhBuilder::ploc:
      return build_ploc(scene.build_references(), {c.max_leaf_size, c.costs, c.ploc_radius});
  }
  throw Error("bvh: unknown builder");
}

}  // namespace rayaccel
