// What every `rayaccel trace` variant (float, --precision double, --instances) shares: the timed passes over the
// rays with their answer buffers and output file (run_trace_passes()), and the keys of the JSON summary line
// (trace_summary(), trace_passes.cpp).
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "cli_common.h"
#include "rayaccel/scene/ray_io.h"

namespace rayaccel::cli {

/// What a trace run measured and produced, for its summary line.
struct TraceFigures {
  std::string accel;  ///< the structure's spec
  std::string scene;  ///< the scene's name
  std::size_t primitives = 0;
  std::size_t rays = 0;
  std::string query;  ///< "intersect", "occluded", "intersect_packets" or "occluded_packets"
  std::vector<double> trace_ms;
  std::size_t hit_count = 0;
  std::size_t memory_bytes = 0;
  std::size_t scene_memory_bytes = 0;
  std::size_t input_memory_bytes = 0;
};
/// The keys every trace summary has (accel, scene, primitives, rays, query, threads, trace_ms[_median],
/// mrays_s_median, hit_count, the memory figures); callers add their build, load and output keys.
nlohmann::json trace_summary(const TraceFigures& figures);

/// The timed passes of a trace and what they found.
struct TracePasses {
  std::vector<double> trace_ms;  ///< one per pass
  std::size_t hit_count = 0;     ///< rays with a closest hit, or occluded ones
};

/// Runs `repeat` timed passes over `ray_count` rays: `occluded(std::span<std::uint8_t>)` when `occlusion`, else
/// `intersect(std::span<HitRecord>)`; then writes `out` when it is not empty (a .occ file, or `write_hits(out,
/// std::span<const HitRecord>)`). HitRecord is any hit record with found().
template <class HitRecord, class Intersect, class Occluded, class WriteHits>
TracePasses run_trace_passes(std::size_t ray_count, bool occlusion, int repeat, const std::string& out,
                             Intersect&& intersect, Occluded&& occluded, WriteHits&& write_hits) {
  std::vector<HitRecord> hits(occlusion ? 0 : ray_count);
  std::vector<std::uint8_t> blocked(occlusion ? ray_count : 0);
  TracePasses passes;
  for (int i = 0; i < repeat; ++i) {
    const Stopwatch clock;
    if (occlusion) {
      occluded(std::span<std::uint8_t>(blocked));
    } else {
      intersect(std::span<HitRecord>(hits));
    }
    passes.trace_ms.push_back(clock.milliseconds());
  }
  passes.hit_count = occlusion ? static_cast<std::size_t>(std::count(blocked.begin(), blocked.end(), std::uint8_t{1}))
                               : static_cast<std::size_t>(std::count_if(
                                     hits.begin(), hits.end(), [](const HitRecord& h) { return h.found(); }));
  if (!out.empty()) {
    if (occlusion) {
      write_occlusion(out, blocked);
    } else {
      write_hits(out, std::span<const HitRecord>(hits));
    }
  }
  return passes;
}

}  // namespace rayaccel::cli
