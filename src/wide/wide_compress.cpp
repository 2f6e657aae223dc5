// Quantising an eight-wide node's child boxes outward into CompressedNode8's 8-bit grid, decoding them, and
// bvh_wide's compressed copy of its nodes (compress=1).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <vector>

#include "rayaccel/wide/compressed_node.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel::wide {
namespace {

/// Below this exponent the grid would reach subnormal steps; a coarser grid is still conservative.
constexpr int kMinExponent = -100;
/// (k + q) * 2^e stays below FLT_MAX for |k + q| < 2^24 only while e + 24 <= 127.
constexpr int kMaxExponent = 127 - 24;
constexpr double kExactIntegers = 16777216.0;  // 2^24: every integer below it times a power of two is a float

struct AxisGrid {
  double origin = 0.0, step = 1.0;
};

/// The finest grid 2^e with origin k * 2^e <= lo and origin + 255 * 2^e >= hi whose 256 points are floats (|k| and
/// |k + 255| below 2^24, e within [kMinExponent, kMaxExponent]); false when none is.
bool fit_grid(double lo, double hi, AxisGrid& grid) {
  int e = kMinExponent;
  const double extent = hi - lo;
  if (extent > 0.0) e = std::max(e, static_cast<int>(std::ceil(std::log2(extent / 254.0))) - 1);
  const double magnitude = std::max(std::fabs(lo), std::fabs(hi));
  if (magnitude > 0.0) e = std::max(e, std::ilogb(magnitude) - 24);  // |k| below 2^24 needs about this much
  for (; e <= kMaxExponent; ++e) {
    const double step = std::ldexp(1.0, e);
    const double k = std::floor(lo / step);  // lo / step is exact in double: lo is a float, step a power of two
    if ((k + 255.0) * step >= hi && std::fabs(k) < kExactIntegers - 256.0) {
      grid = {k * step, step};
      return true;
    }
  }
  return false;
}

/// The largest grid index whose point is <= x, or the smallest whose point is >= x (up); -1 when outside 0..255.
int grid_index(const AxisGrid& grid, float x, bool up) {
  double q = (static_cast<double>(x) - grid.origin) / grid.step;
  q = up ? std::ceil(q) : std::floor(q);
  // The subtraction may round in double where x's and the origin's exponents lie far apart: step back over it,
  // comparing exact values (grid points are floats, x is one).
  while (!up && q >= 0.0 && grid.origin + q * grid.step > x) q -= 1.0;
  while (up && q <= 255.0 && grid.origin + q * grid.step < x) q += 1.0;
  return q >= 0.0 && q <= 255.0 ? static_cast<int>(q) : -1;
}

}  // namespace

bool compress_node(const Node<8>& node, CompressedNode8& out) {
  out = CompressedNode8{};
  for (int lane = 0; lane < 8; ++lane) out.child[lane] = node.child[lane];
  for (unsigned octant = 0; octant < 8; ++octant) {
    const unsigned word = node.order[octant];
    for (int byte = 0; byte < 3; ++byte) out.order[octant][byte] = static_cast<std::uint8_t>(word >> (8 * byte));
  }
  for (int a = 0; a < 3; ++a) {
    double lo = INFINITY, hi = -INFINITY;
    for (int lane = 0; lane < 8; ++lane) {
      if (node.child[lane] == kEmptyChild) continue;
      const float clo = node.bounds[a][0][lane], chi = node.bounds[a][1][lane];
      if (!std::isfinite(clo) || !std::isfinite(chi) || clo > chi) return false;
      lo = std::min(lo, static_cast<double>(clo));
      hi = std::max(hi, static_cast<double>(chi));
    }
    if (lo > hi) continue;  // no used child
    AxisGrid grid;
    if (!fit_grid(lo, hi, grid)) return false;
    out.origin[a] = static_cast<float>(grid.origin);
    out.scale[a] = static_cast<float>(grid.step);
    for (int lane = 0; lane < 8; ++lane) {
      if (node.child[lane] == kEmptyChild) continue;
      const int qlo = grid_index(grid, node.bounds[a][0][lane], false);
      const int qhi = grid_index(grid, node.bounds[a][1][lane], true);
      if (qlo < 0 || qhi < 0) return false;
      out.q[a][0][lane] = static_cast<std::uint8_t>(qlo);
      out.q[a][1][lane] = static_cast<std::uint8_t>(qhi);
    }
  }
  return true;
}

AABB decoded_child_bounds(const CompressedNode8& node, int lane) {
  AABB box;
  for (int a = 0; a < 3; ++a) {
    // Exact: the grid's points are floats (compress_node), so neither the product nor the sum rounds.
    box.lo[a] = node.origin[a] + static_cast<float>(node.q[a][0][lane]) * node.scale[a];
    box.hi[a] = node.origin[a] + static_cast<float>(node.q[a][1][lane]) * node.scale[a];
  }
  return box;
}

void WideBvh::compress_nodes() {
  compressed_nodes8_.clear();
  if (!config_.compress || width_ != 8 || nodes8_.empty()) return;
  compressed_nodes8_.resize(nodes8_.size());
  std::atomic<bool> fits{true};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nodes8_.size(), 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      if (!compress_node(nodes8_[i], compressed_nodes8_[i])) fits = false;
    }
  });
  if (!fits) compressed_nodes8_ = {};
}

void WideBvh::validate_compressed(std::vector<std::string>& problems) const {
  if (compressed_nodes8_.empty()) return;
  if (compressed_nodes8_.size() != nodes8_.size()) {
    problems.push_back("compressed node count " + std::to_string(compressed_nodes8_.size()) + " differs from " +
                       std::to_string(nodes8_.size()));
    return;
  }
  for (std::size_t i = 0; i < nodes8_.size(); ++i) {
    const CompressedNode8& c = compressed_nodes8_[i];
    const std::string where = "compressed node " + std::to_string(i);
    for (unsigned octant = 0; octant < 8; ++octant) {
      if (child_order(c, octant) != child_order(nodes8_[i], octant)) {
        problems.push_back(where + ": child order differs");
        return;
      }
    }
    for (int lane = 0; lane < 8; ++lane) {
      if (c.child[lane] != nodes8_[i].child[lane]) {
        problems.push_back(where + ": child " + std::to_string(lane) + " differs");
        return;
      }
      if (c.child[lane] != kEmptyChild && !decoded_child_bounds(c, lane).contains(child_bounds(nodes8_[i], lane))) {
        problems.push_back(where + ": child " + std::to_string(lane) + "'s grid box does not contain its box");
        return;
      }
    }
  }
}

}  // namespace rayaccel::wide
