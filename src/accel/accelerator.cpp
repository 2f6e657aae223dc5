// Batch splitting shared by every accelerator.
#include "rayaccel/accel/accelerator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <string>

#include "rayaccel/core/error.h"

namespace rayaccel::detail {

void parallel_for_rays(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
  constexpr std::size_t kGrain = 64;  // rays per task: enough to hide scheduling, small enough to balance
  // Rays are traced in the caller's floating-point environment (MXCSR: rounding, flush-to-zero, denormals-are-zero),
  // as a loop on the calling thread would be. Without a context that captures it, TBB tasks run with the settings
  // its default context captured when TBB was first used, which may be another library's: Embree's build leaves
  // FTZ/DAZ there, and with DAZ a ray origin 2^-149 above a floor reads as lying on it.
  tbb::task_group_context context(tbb::task_group_context::bound,
                                  tbb::task_group_context::default_traits | tbb::task_group_context::fp_settings);
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, count, kGrain),
      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); }, context);
}

void parallel_for_packets(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
  parallel_for_rays((count + kPacketSize - 1) / kPacketSize, [&](std::size_t begin, std::size_t end) {
    body(begin * kPacketSize, std::min(end * kPacketSize, count));
  });
}

void check_batch_sizes(std::size_t rays, std::size_t outputs, std::size_t stats) {
  if (outputs != rays) {
    throw Error("batch: " + std::to_string(rays) + " rays but " + std::to_string(outputs) + " output slots");
  }
  if (stats != 0 && stats != rays) {
    throw Error("batch: " + std::to_string(rays) + " rays but " + std::to_string(stats) + " statistics records");
  }
}

}  // namespace rayaccel::detail
