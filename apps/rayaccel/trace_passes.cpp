// The summary line's common keys (trace_passes.h).
#include "trace_passes.h"

namespace rayaccel::cli {

nlohmann::json trace_summary(const TraceFigures& f) {
  const double trace_median = median(f.trace_ms);
  return {
      {"accel", f.accel},
      {"scene", f.scene},
      {"primitives", f.primitives},
      {"rays", f.rays},
      {"query", f.query},
      {"threads", ThreadLimit::active()},
      {"trace_ms_median", trace_median},
      {"trace_ms", f.trace_ms},
      {"mrays_s_median", trace_median > 0.0 ? static_cast<double>(f.rays) / (trace_median * 1e3) : 0.0},
      {"hit_count", f.hit_count},
      {"memory_bytes", f.memory_bytes},
      {"scene_memory_bytes", f.scene_memory_bytes},
      {"input_memory_bytes", f.input_memory_bytes},
  };
}

}  // namespace rayaccel::cli
