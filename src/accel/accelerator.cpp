// Batch splitting shared by every accelerator.
#include "rayaccel/accel/accelerator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <string>

#include "rayaccel/core/error.h"

namespace rayaccel::detail {

void parallel_for_rays(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
  constexpr std::size_t kGrain = 64;  // rays per task: enough to hide scheduling, small enough to balance
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
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
