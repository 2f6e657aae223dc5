// bvh_wide's option table (WideBvhOptions's keys, ranges and docs) and its registration.
#include "rayaccel/wide/wide_bvh_registry.h"

#include <memory>
#include <string>
#include <utility>

#include "rayaccel/core/error.h"
#include "rayaccel/wide/wide_bvh.h"
#include "rayaccel/wide/wide_bvh_file.h"

namespace rayaccel::wide {

const OptionTable<WideBvhOptions>& wide_bvh_option_table() {
  using O = WideBvhOptions;
  static const OptionTable<O> table = [] {
    OptionTable<O> t("bvh_wide");
    t.choice("width", &O::width, {{"auto", 0}, {"4", 4}, {"8", 8}},
             "children per node: 4 (SSE2), 8 (AVX2; 4 on CPUs without it), auto");
    t.choice("isa", &O::isa, {{"best", WideIsa::best}, {"avx2", WideIsa::avx2}},
             "instruction set of the eight-wide kernels: best (AVX-512 build where the CPU has it, else AVX2) or avx2");
    t.integer("bins", [](O& o) -> std::uint32_t& { return o.binary.bin_count; }, 2, 64,
              "SAH bins per axis of the binary build");
    t.real("presplit", &O::presplit, RealRange::closed(0.0, 4.0),
           "triangle pre-splitting (Karras & Aila 2013): extra references as a fraction of the triangle count; 0 "
           "turns it off");
    t.real("presplit_threshold", &O::presplit_threshold, RealRange::at_least(0.0),
           "pre-split only scenes whose pre-splitting potential (box area wasted at coarse grid planes over the scene "
           "box area; reported as presplit_potential) is at least this; 0 pre-splits every triangle scene");
    t.real("spatial", &O::spatial, RealRange::closed(0.0, 1.0),
           "spatial splits in the binary build (SBVH, Stich et al. 2009): extra references as a fraction of the "
           "triangle count; 0 turns them off; above 0 replaces presplit");
    t.integer("reinsert", &O::reinsert, 0, 64,
              "rounds of insertion-based optimisation of the binary tree (Bittner et al. 2013); 0 turns it off");
    t.choice("collapse", &O::collapse, {{"area", WideCollapse::area}, {"sah", WideCollapse::sah}},
             "how binary nodes are gathered into wide ones: sah (the least SAH cost, Ylitie et al. 2017's dynamic "
             "programme) or area (open the child of largest surface area)");
    t.rule([](const O& o) {
      if (o.width == 4 && o.isa != WideIsa::best) {
        throw Error("bvh_wide: isa=avx2 applies to the eight-wide kernels, not width=4");
      }
    });
    return t;
  }();
  return table;
}

WideBvh::WideBvh(WideBvhOptions config) : config_(config) { wide_bvh_option_table().check(config_); }

void register_wide_bvh(std::vector<AcceleratorInfo>& registry) {
  AcceleratorInfo info = registry_entry<WideBvh>(
      wide_bvh_option_table(),
      "4- or 8-wide SIMD BVH (SoA child boxes, Triangle4 leaves) collapsed from a binned SAH tree; AVX2 (or its "
      "AVX-512 build) when the CPU has it",
      {"bvh_wide", "bvh_wide:width=4", "bvh_wide:width=8,isa=avx2", "bvh_wide:presplit=0",
       "bvh_wide:presplit_threshold=0", "bvh_wide:collapse=area", "bvh_wide:spatial=0.2", "bvh_wide:reinsert=0"});
  info.saved_spec = wide_bvh_file_spec;
  registry.push_back(std::move(info));
}

}  // namespace rayaccel::wide
