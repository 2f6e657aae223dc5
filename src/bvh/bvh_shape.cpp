// The builder dispatch of Bvh<BV> (one table from BvhBuilder to builder) and the option table.
#include <string>
#include <utility>
#include <vector>

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

const OptionTable<BvhOptions>& bvh_option_table() {
  using O = BvhOptions;
  static const OptionTable<O> table = [] {
    OptionTable<O> t("bvh");
    std::vector<std::pair<std::string, BvhBuilder>> builders;
    for (BvhBuilder b : {BvhBuilder::binned, BvhBuilder::sweep, BvhBuilder::sbvh, BvhBuilder::lbvh, BvhBuilder::ploc}) {
      builders.emplace_back(to_string(b), b);
    }
    t.choice("builder", &O::builder, builders,
             "binned SAH (Wald 2007), sweep SAH, sbvh (spatial splits, Stich 2009), lbvh (Morton, Lauterbach 2009), "
             "ploc (Meister & Bittner 2018)");
    t.integer("leaf_size", &O::max_leaf_size, 1, 255, "most primitives per leaf");
    t.real("traversal_cost", [](O& o) -> float& { return o.costs.traversal; }, RealRange::at_least(0.0),
           "SAH cost of visiting an interior node");
    t.real("intersection_cost", [](O& o) -> float& { return o.costs.intersection; }, RealRange::positive(),
           "SAH cost of one primitive test");
    t.integer("bins", &O::bin_count, 2, 64, "bins per axis for binned SAH and SBVH");
    t.real("max_growth", &O::max_growth, RealRange::closed(1.0, 16.0),
           "SBVH: most references as a multiple of the primitive count");
    t.real("overlap_alpha", &O::overlap_alpha, RealRange::at_least(0.0),
           "SBVH: child overlap (fraction of root area) that triggers spatial splits");
    t.integer("ploc_radius", &O::ploc_radius, 1, 256, "PLOC: neighbours searched on each side in Morton order");
    return t;
  }();
  return table;
}

BuildTree build_bvh_shape(const Scene& scene, const BvhOptions& c) {
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
