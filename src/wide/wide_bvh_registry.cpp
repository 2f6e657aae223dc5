// Registration of bvh_wide: its options, their defaults (WideBvhConfig's) and their parsing.
#include "rayaccel/wide/wide_bvh_registry.h"

#include <memory>
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel::wide {

/// Defaults of the registry's presplit options: WideBvhConfig's defaults, written as option strings.
constexpr const char* kDefaultPresplit = "0.1";
constexpr const char* kDefaultPresplitThreshold = "4";

void register_wide_bvh(std::vector<AcceleratorInfo>& registry) {
  const BinnedSahConfig defaults = WideBvhConfig{}.binary;
  registry.push_back(
      {"bvh_wide",
       "4- or 8-wide SIMD BVH (SoA child boxes, Triangle4 leaves) collapsed from a binned SAH tree; AVX2 (or its "
       "AVX-512 build) when the CPU has it",
       {{"width", OptionType::choice, "auto", "children per node: 4 (SSE2), 8 (AVX2; 4 on CPUs without it), auto",
         {"auto", "4", "8"}},
        {"isa", OptionType::choice, "best",
         "instruction set of the eight-wide kernels: best (AVX-512 build where the CPU has it, else AVX2) or avx2",
         {"best", "avx2"}},
        {"bins", OptionType::integer, std::to_string(defaults.bin_count), "SAH bins per axis of the binary build (2..64)",
         {}},
        {"presplit", OptionType::real, kDefaultPresplit,
         "triangle pre-splitting (Karras & Aila 2013): extra references as a fraction of the triangle count, 0..4; 0 "
         "turns it off",
         {}},
        {"presplit_threshold", OptionType::real, kDefaultPresplitThreshold,
         "pre-split only scenes whose pre-splitting potential (box area wasted at coarse grid planes over the scene "
         "box area; reported as presplit_potential) is at least this; 0 pre-splits every triangle scene",
         {}}},
       {"bvh_wide", "bvh_wide:width=4", "bvh_wide:width=8,isa=avx2", "bvh_wide:presplit=0",
        "bvh_wide:presplit_threshold=0"},
       [](const Options& options) {
         WideBvhConfig config;
         const std::string& width = options.get("width");
         config.width = width == "auto" ? 0 : std::stoi(width);
         config.isa = options.get("isa") == "avx2" ? WideIsa::avx2 : WideIsa::best;
         if (config.width == 4 && config.isa != WideIsa::best) {
           throw Error("bvh_wide: isa=" + options.get("isa") + " applies to the eight-wide kernels, not width=4");
         }
         const long long bins = options.get_int("bins");
         if (bins < 2 || bins > 64) throw Error("bvh_wide: bins must be in 2..64, got " + std::to_string(bins));
         config.binary.bin_count = static_cast<std::uint32_t>(bins);
         const double presplit = options.get_real("presplit");
         if (!(presplit >= 0.0 && presplit <= 4.0)) {
           throw Error("bvh_wide: presplit must be in [0, 4], got " + options.get("presplit"));
         }
         config.presplit = static_cast<float>(presplit);
         const double threshold = options.get_real("presplit_threshold");
         if (!(threshold >= 0.0 && threshold <= 1e30)) {
           throw Error("bvh_wide: presplit_threshold must be a finite number >= 0, got " + options.get("presplit_threshold"));
         }
         config.presplit_threshold = static_cast<float>(threshold);
         return std::make_unique<WideBvh>(config);
       }});
}

}  // namespace rayaccel::wide
