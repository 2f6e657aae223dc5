// The structures the query tests run over: every spec of `rayaccel list --names` that answers queries.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "rayaccel/accel/registry.h"

namespace rayaccel::testing {

/// Every variant whose structure answers all-hits and closest-point queries, built over `scene`; brute force first.
inline std::vector<std::unique_ptr<Accelerator>> query_structures(const Scene& scene) {
  std::vector<std::unique_ptr<Accelerator>> out;
  for (const std::string& spec : accelerator_variant_names()) {
    auto accel = make_accelerator(spec);
    if (!accel->supports_queries()) continue;
    accel->build(scene);
    out.push_back(std::move(accel));
  }
  return out;
}

}  // namespace rayaccel::testing
