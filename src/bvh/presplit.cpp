// Triangle pre-splitting: priorities from box waste and grid-plane depth, the budget shared by bisection on the
// scale factor, and recursive splitting at grid planes with conservative clipping (see presplit.h).
#include "rayaccel/bvh/presplit.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_scan.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <functional>

#include "rayaccel/geometry/clip_polygon.h"

namespace rayaccel {

namespace {

/// Levels of the plane hierarchy per axis: finer planes than 2^-24 of the scene extent are below float precision.
constexpr int kLevels = 24;
constexpr double kCells = double(1 << kLevels);

struct GridPlane {
  int axis = -1;  ///< -1: no grid plane crosses the box
  int depth = 0;  ///< 3 * level + axis (Morton order: x planes first within a level)
  float position = 0.0f;
};

/// The power-of-two grid over the scene box.
class PlaneGrid {
 public:
  explicit PlaneGrid(const AABB& scene_box) : lo_(scene_box.lo) {
    for (int a = 0; a < 3; ++a) {
      const double extent = double(scene_box.hi[a]) - double(scene_box.lo[a]);
      scale_[a] = extent > 0.0 ? kCells / extent : 0.0;
      cell_[a] = extent > 0.0 ? extent / kCells : 0.0;
    }
  }

  /// The plane of smallest depth that lies strictly inside `box` (both sides keep a part of positive width).
  GridPlane coarsest_crossing(const AABB& box) const {
    GridPlane best;
    for (int a = 0; a < 3; ++a) {
      if (scale_[a] == 0.0) continue;
      const double u_lo = std::clamp((double(box.lo[a]) - lo_[a]) * scale_[a], 0.0, kCells);
      const double u_hi = std::clamp((double(box.hi[a]) - lo_[a]) * scale_[a], 0.0, kCells);
      // Grid lines g with u_lo < g < u_hi: g in (floor(u_lo), ceil(u_hi) - 1] (truncation is floor for u >= 0).
      const auto q_lo = static_cast<std::int64_t>(u_lo);
      auto q_hi = static_cast<std::int64_t>(u_hi);
      if (static_cast<double>(q_hi) == u_hi) --q_hi;
      if (q_hi <= q_lo) continue;
      // The coarsest line in (q_lo, q_hi] is q_hi with the bits below their highest difference cleared.
      const int bit = 63 - __builtin_clzll(static_cast<std::uint64_t>(q_lo ^ q_hi));
      const std::int64_t line = (q_hi >> bit) << bit;
      const int depth = 3 * (kLevels - 1 - bit) + a;
      if (best.axis >= 0 && depth >= best.depth) continue;
      const auto position = static_cast<float>(lo_[a] + double(line) * cell_[a]);
      if (!(position > box.lo[a] && position < box.hi[a])) continue;  // lost to rounding: not a useful cut
      best = {a, depth, position};
    }
    return best;
  }

 private:
  Vec3 lo_;
  double scale_[3] = {0, 0, 0};
  double cell_[3] = {0, 0, 0};
};

/// 2^-depth for every depth a GridPlane can have.
double depth_weight(int depth) {
  static const auto table = [] {
    std::array<double, 3 * kLevels> t{};
    for (int d = 0; d < 3 * kLevels; ++d) t[d] = std::ldexp(1.0, -d);
    return t;
  }();
  return table[depth];
}

/// Cube root to about 1e-6 relative (priorities only share out a budget of pieces; a third Newton step is not worth
/// its time: BENCHMARKS.md, "Option choices") without a library call: a first guess from the exponent bits
/// divided by three, then two Newton steps. x > 0 and finite.
double fast_cbrt(double x) {
  const auto bits = std::bit_cast<std::uint64_t>(x);
  double y = std::bit_cast<double>(bits / 3 + 0x2A9F7893782DA1CEull);  // within ~10% of cbrt(x)
  for (int i = 0; i < 2; ++i) y -= (y * y * y - x) / (3.0 * y * y);
  return y;
}

/// 2^-d (A_box - A_ideal) of a triangle with box `box` (see presplit.h), 0 when no grid plane crosses the box or the
/// box wastes nothing.
double weighted_waste(const std::array<Vec3, 3>& t, const AABB& box, const PlaneGrid& grid) {
  const GridPlane plane = grid.coarsest_crossing(box);
  if (plane.axis < 0) return 0.0;
  const double ux = double(t[1].x) - t[0].x, uy = double(t[1].y) - t[0].y, uz = double(t[1].z) - t[0].z;
  const double vx = double(t[2].x) - t[0].x, vy = double(t[2].y) - t[0].y, vz = double(t[2].z) - t[0].z;
  const double ideal = std::fabs(uy * vz - uz * vy) + std::fabs(uz * vx - ux * vz) + std::fabs(ux * vy - uy * vx);
  const Vec3 e = box.extent();
  const double box_area = 2.0 * (double(e.x) * e.y + double(e.y) * e.z + double(e.z) * e.x);
  const double waste = box_area - ideal;
  if (!(waste > 0.0)) return 0.0;
  return waste * depth_weight(plane.depth);
}

double priority(const std::array<Vec3, 3>& t, const AABB& box, const PlaneGrid& grid, double exponent) {
  const double weighted = weighted_waste(t, box, grid);
  if (!(weighted >= 0x1p-1000) || !std::isfinite(weighted)) return 0.0;
  return exponent == 1.0 / 3.0 ? fast_cbrt(weighted) : std::pow(weighted, exponent);
}

/// Writes at most `pieces` boxes covering the part of triangle t inside `box` to out[count...]; returns the new count.
/// `box` must be the (conservative) bounds of that part.
std::uint32_t split_box(const std::array<Vec3, 3>& t, AABB box, std::uint32_t pieces, const PlaneGrid& grid,
                        PrimRef* out, std::uint32_t count, std::uint32_t prim_id) {
  for (;;) {
    const GridPlane plane = pieces > 1 ? grid.coarsest_crossing(box) : GridPlane{};
    if (plane.axis < 0) break;
    AABB below = box, above = box;
    below.hi[plane.axis] = plane.position;
    above.lo[plane.axis] = plane.position;
    // A part that is flat on the plane itself holds only points on the plane, which the other side's part (closed
    // at the plane) holds too: treat it as empty rather than spend a reference on it.
    auto part = [&](const AABB& half) {
      const AABB b = clip_triangle_to_box(t[0], t[1], t[2], half);
      const bool on_plane = b.lo[plane.axis] == plane.position && b.hi[plane.axis] == plane.position;
      return on_plane ? AABB{} : b;
    };
    const AABB left = part(below);
    const AABB right = part(above);
    if (left.is_empty() == right.is_empty()) {
      if (left.is_empty()) break;  // cannot happen for a box around part of the triangle; keep the box whole
      const double wl = left.extent()[left.largest_axis()], wr = right.extent()[right.largest_axis()];
      const double share = wl + wr > 0.0 ? wl / (wl + wr) : 0.5;
      const auto left_pieces = static_cast<std::uint32_t>(
          std::clamp(std::round(share * pieces), 1.0, static_cast<double>(pieces - 1)));
      count = split_box(t, left, left_pieces, grid, out, count, prim_id);
      return split_box(t, right, pieces - left_pieces, grid, out, count, prim_id);
    }
    // The part lies on one side of the plane (its box was conservative): go on with the smaller box and the same
    // piece count. The box shrinks strictly on plane.axis, so this ends after at most kLevels steps per axis.
    box = left.is_empty() ? right : left;
  }
  out[count] = {box, prim_id};
  return count + 1;
}

}  // namespace

double presplit_potential(const Scene& scene, std::uint32_t max_samples) {
  if (scene.kind() != PrimitiveKind::triangles || scene.primitive_count() == 0) return 0.0;
  const AABB& box = scene.bounds();
  const double ex = double(box.hi.x) - box.lo.x, ey = double(box.hi.y) - box.lo.y, ez = double(box.hi.z) - box.lo.z;
  const double scene_area = 2.0 * (ex * ey + ey * ez + ez * ex);
  if (!(scene_area > 0.0) || !std::isfinite(scene_area)) return 0.0;
  const PlaneGrid grid(scene.bounds());
  const std::uint32_t n = scene.primitive_count();
  const std::uint32_t stride = max_samples == 0 ? 1 : std::max<std::uint32_t>(1, (n + max_samples - 1) / max_samples);
  // A deterministic reduction: the same sum, in the same order, with any number of threads.
  const std::size_t samples = (std::size_t{n} + stride - 1) / stride;
  const double sum = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, samples, 1024), 0.0,
      [&](const tbb::blocked_range<std::size_t>& range, double partial) {
        for (std::size_t k = range.begin(); k != range.end(); ++k) {
          const auto id = static_cast<std::uint32_t>(k * stride);
          if (!scene.is_valid(id)) continue;
          const double weighted = weighted_waste(scene.triangle(id), scene.primitive_bounds(id), grid);
          if (std::isfinite(weighted)) partial += weighted;
        }
        return partial;
      },
      std::plus<>());
  return sum * stride / scene_area;
}

PresplitResult presplit_references(const Scene& scene, const PresplitOptions& config) {
  PresplitResult result;
  const bool splits = scene.kind() == PrimitiveKind::triangles && config.fraction > 0.0f;
  const std::size_t valid = scene.valid_count();
  const auto budget = splits ? static_cast<std::uint64_t>(std::floor(double(config.fraction) * double(valid))) : 0;
  // Room for every extra piece: they are appended, and the references of unsplit triangles are never moved.
  result.refs = scene.build_references(budget);
  PrimRefs& refs = result.refs;
  const std::size_t n = refs.size();
  if (budget == 0 || n == 0) return result;
  const PlaneGrid grid(scene.bounds());

  // Priorities and their sum. The exponent 1/3 (the default) is taken as exactly a cube root.
  const double exponent =
      config.priority_exponent == 1.0f / 3.0f ? 1.0 / 3.0 : static_cast<double>(config.priority_exponent);
  // The deterministic reduction adds in the same order on every run, so beta and the tree do not vary.
  UninitializedHugePageVector<double> prio(n);  // written below, in parallel
  const double total = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, n, 1024), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double sum) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          prio[i] = priority(scene.triangle(refs[i].prim_id), refs[i].bounds, grid, exponent);
          sum += prio[i];
        }
        return sum;
      },
      std::plus<>());
  if (!(total > 0.0) || !std::isfinite(total)) return result;

  // Largest beta whose extra pieces sum(floor(beta * p)) fit the budget: beta = budget / total always fits, and
  // (budget + n) / total always reaches it, so bisect between the two. Only priorities with beta_hi * p >= 1 can
  // get a piece, usually a small part of them: the bisection runs over those alone.
  auto extra_for = [](double beta, double p) { return static_cast<std::uint64_t>(std::floor(beta * p)); };
  double beta_lo = double(budget) / total, beta_hi = double(budget + n) / total;
  std::vector<std::uint32_t> candidates;  // indices of the triangles that can get a piece
  for (std::size_t i = 0; i < n; ++i) {
    if (beta_hi * prio[i] >= 1.0) candidates.push_back(static_cast<std::uint32_t>(i));
  }
  auto extra_total = [&](double beta) {
    std::uint64_t sum = 0;
    for (const std::uint32_t i : candidates) sum += extra_for(beta, prio[i]);
    return sum;
  };
  std::uint64_t extra_lo = extra_total(beta_lo);
  while (beta_lo > 0.0 && extra_lo > budget) extra_lo = extra_total(beta_lo *= 0.5);  // rounding; rarely taken
  for (int step = 0; step < 20 && extra_lo < budget; ++step) {
    const double mid = 0.5 * (beta_lo + beta_hi);
    const std::uint64_t extra = extra_total(mid);
    if (extra <= budget) {
      beta_lo = mid;
      extra_lo = extra;
    } else {
      beta_hi = mid;
    }
  }
  const double beta = beta_lo;

  // Only candidates can be split. Each split triangle keeps its first piece in its own slot; the others go to the
  // slots after the n references, at its place in the order of candidates (an exclusive prefix sum of extras).
  std::vector<std::uint64_t> first_extra(candidates.size() + 1, 0);
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    first_extra[k + 1] = first_extra[k] + extra_for(beta, prio[candidates[k]]);
  }
  refs.resize(n + first_extra.back());  // within the reserved capacity: the n references stay where they are
  const std::size_t block = 64;
  result.split_triangles = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, candidates.size(), block), std::uint32_t{0},
      [&](const tbb::blocked_range<std::size_t>& r, std::uint32_t split_count) {
        std::vector<PrimRef> pieces;
        for (std::size_t k = r.begin(); k != r.end(); ++k) {
          const std::size_t i = candidates[k];
          const auto extra = static_cast<std::uint32_t>(first_extra[k + 1] - first_extra[k]);
          if (extra == 0) continue;
          pieces.resize(extra + 1);
          const std::uint32_t made = split_box(scene.triangle(refs[i].prim_id), refs[i].bounds, extra + 1, grid,
                                               pieces.data(), 0, refs[i].prim_id);
          // A triangle may make fewer pieces than planned: its unused slots get an empty box, removed below.
          refs[i] = pieces[0];
          PrimRef* out = refs.data() + n + first_extra[k];
          for (std::uint32_t p = 1; p <= extra; ++p) out[p - 1] = p < made ? pieces[p] : PrimRef{AABB::empty(), 0};
          split_count += made > 1 ? 1 : 0;
        }
        return split_count;
      },
      std::plus<>());
  const auto tail = std::remove_if(refs.begin() + static_cast<std::ptrdiff_t>(n), refs.end(),
                                   [](const PrimRef& ref) { return ref.bounds.is_empty(); });
  refs.erase(tail, refs.end());
  return result;
}

}  // namespace rayaccel
