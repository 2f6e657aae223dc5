// Grid building blocks shared by the uniform and two-level grids: resolution choice (Wald et al. 2006, Ize et al.
// 2007), conservative binning of primitives into cells (boxes, then the exact SAT test for triangles) and compact
// count / prefix-sum / fill cell lists (Lagae & Dutre 2008).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <algorithm>
#include <cmath>

#include "rayaccel/accel/uniform_grid.h"
#include "rayaccel/geometry/triangle_box_overlap.h"

namespace rayaccel {

std::array<int, 3> grid_resolution(const Vec3& extent, std::size_t n, double density, int max_resolution,
                                   std::uint64_t max_cells) {
  std::array<int, 3> res{1, 1, 1};
  if (n == 0) return res;
  const double target = density * density * density * double(n);
  // Axes whose share would be below one cell get exactly one; the rest split the target by their extents.
  bool active[3] = {extent.x > 0.0f, extent.y > 0.0f, extent.z > 0.0f};
  double scale = 0.0;
  for (int round = 0; round < 3; ++round) {
    int dims = 0;
    double volume = 1.0;
    for (int a = 0; a < 3; ++a) {
      if (active[a]) { ++dims; volume *= extent[a]; }
    }
    if (dims == 0) break;
    scale = std::pow(target / volume, 1.0 / dims);
    bool changed = false;
    for (int a = 0; a < 3; ++a) {
      if (active[a] && extent[a] * scale < 1.0) { active[a] = false; changed = true; }
    }
    if (!changed) break;
  }
  for (int a = 0; a < 3; ++a) {
    const double cells = active[a] ? std::round(extent[a] * scale) : 1.0;
    res[a] = int(std::clamp(cells, 1.0, double(max_resolution)));
  }
  const double total = double(res[0]) * res[1] * res[2];
  if (total > double(max_cells)) {
    const double shrink = std::cbrt(double(max_cells) / total);
    for (int a = 0; a < 3; ++a) res[a] = std::max(1, int(std::floor(res[a] * shrink)));
  }
  return res;
}

std::array<int, 3> limit_references(std::array<int, 3> res, const AABB& box, std::span<const PrimRef> refs,
                                    float pad, std::size_t budget) {
  for (;;) {
    const GridFrame f = GridFrame::make(box, res);
    double pairs = 0.0;
    for (const PrimRef& ref : refs) {
      double cells = 1.0;
      for (int a = 0; a < 3; ++a) {
        cells *= double(f.cell_of(ref.bounds.hi[a] + pad, a) - f.cell_of(ref.bounds.lo[a] - pad, a) + 1);
      }
      pairs += cells;
    }
    if (pairs <= double(budget) || (res[0] == 1 && res[1] == 1 && res[2] == 1)) return res;
    for (int a = 0; a < 3; ++a) res[a] = std::max(1, res[a] * 3 / 4);
  }
}

std::array<int, 3> level_resolution(const AABB& box, std::span<const PrimRef> refs, float pad, double density,
                                    int max_resolution, std::uint64_t max_cells, std::size_t per_primitive) {
  const auto res = grid_resolution(box.extent(), refs.size(), density, max_resolution, max_cells);
  const std::size_t budget = grid_reference_budget(refs.size(), per_primitive);
  return limit_references(limit_to_precision(res, box), box, refs, pad, budget);
}

namespace {

/// Calls emit(cell) for every cell of `f` the primitive is binned to. Triangles under the exact rule are located by
/// halving the cell range, testing each sub-range's box, so a large triangle costs about as many tests as cells it
/// really touches rather than cells its box spans.
template <class Emit>
void rasterize(const Scene& scene, const PrimRef& ref, const GridFrame& f, float pad, bool exact, Emit&& emit) {
  std::array<int, 3> lo, hi;
  for (int a = 0; a < 3; ++a) {
    lo[a] = f.cell_of(ref.bounds.lo[a] - pad, a);
    hi[a] = f.cell_of(ref.bounds.hi[a] + pad, a);
  }
  if (!exact || scene.kind() != PrimitiveKind::triangles) {
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) emit(f.linear(x, y, z));
    return;
  }
  const auto& tri = scene.triangle(ref.prim_id);
  const auto visit = [&](const auto& self, std::array<int, 3> l, std::array<int, 3> h) -> void {
    const AABB box{{f.plane(0, l[0]) - pad, f.plane(1, l[1]) - pad, f.plane(2, l[2]) - pad},
                   {f.plane(0, h[0] + 1) + pad, f.plane(1, h[1] + 1) + pad, f.plane(2, h[2] + 1) + pad}};
    if (!triangle_overlaps_box(tri[0], tri[1], tri[2], box)) return;
    int axis = 0;
    for (int a = 1; a < 3; ++a) {
      if (h[a] - l[a] > h[axis] - l[axis]) axis = a;
    }
    if (h[axis] == l[axis]) { emit(f.linear(l[0], l[1], l[2])); return; }
    const int mid = (l[axis] + h[axis]) / 2;
    std::array<int, 3> h_left = h, l_right = l;
    h_left[axis] = mid;
    l_right[axis] = mid + 1;
    self(self, l, h_left);
    self(self, l_right, h);
  };
  visit(visit, lo, hi);
}

}  // namespace

CellLists bin_primitives(const Scene& scene, std::span<const PrimRef> refs, const GridFrame& frame, float pad,
                         bool exact) {
  // Pass 1 (parallel over fixed chunks, so the output order is deterministic): (cell, id) pairs in reference order.
  constexpr std::size_t kChunk = 1024;
  const std::size_t chunks = (refs.size() + kChunk - 1) / kChunk;
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> pairs(chunks);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t chunk = r.begin(); chunk != r.end(); ++chunk) {
      auto& out = pairs[chunk];
      const std::size_t end = std::min(refs.size(), (chunk + 1) * kChunk);
      for (std::size_t i = chunk * kChunk; i < end; ++i) {
        rasterize(scene, refs[i], frame, pad, exact, [&](std::uint32_t cell) { out.emplace_back(cell, refs[i].prim_id); });
      }
    }
  }, tbb::simple_partitioner());
  // Pass 2: count, prefix sum, fill.
  CellLists lists;
  lists.offsets.assign(std::size_t(frame.cell_count()) + 1, 0);
  std::size_t total = 0;
  for (const auto& chunk : pairs) {
    total += chunk.size();
    for (const auto& [cell, id] : chunk) ++lists.offsets[cell + 1];
  }
  for (std::size_t c = 1; c < lists.offsets.size(); ++c) lists.offsets[c] += lists.offsets[c - 1];
  lists.ids.resize(total);
  std::vector<std::uint32_t> cursor(lists.offsets.begin(), lists.offsets.end() - 1);
  for (const auto& chunk : pairs) {
    for (const auto& [cell, id] : chunk) lists.ids[cursor[cell]++] = id;
  }
  return lists;
}

bool primitive_overlaps_cell(const Scene& scene, std::uint32_t id, const AABB& cell, float pad, bool exact) {
  const AABB grown{cell.lo - Vec3{pad}, cell.hi + Vec3{pad}};
  if (scene.kind() != PrimitiveKind::triangles) return grown.overlaps(scene.primitive_bounds(id));
  // A triangle's vertices are read once, for its box and for the exact test (the scene stores no boxes).
  if (!scene.is_valid(id)) return false;
  const auto t = scene.triangle(id);
  if (!grown.overlaps(AABB::of_point(t[0]).extend(t[1]).extend(t[2]))) return false;
  return !exact || triangle_overlaps_box(t[0], t[1], t[2], grown);
}

void validate_cell_lists(const Scene& scene, std::span<const std::uint32_t> offsets,
                         std::span<const std::uint32_t> ids, const GridFrame& frame, float pad, bool exact,
                         std::vector<std::uint8_t>& seen, std::vector<std::string>& problems) {
  const std::size_t cells = frame.cell_count();
  if (offsets.size() != cells + 1) {
    problems.push_back("offset array has " + std::to_string(offsets.size()) + " entries for " +
                       std::to_string(cells) + " cells");
    return;
  }
  if (offsets.back() > ids.size()) {
    problems.push_back("offsets end at " + std::to_string(offsets.back()) + ", past the " +
                       std::to_string(ids.size()) + " references");
    return;
  }
  for (std::size_t c = 0; c < cells; ++c) {
    if (offsets[c] > offsets[c + 1]) {
      problems.push_back("offsets decrease at cell " + std::to_string(c));
      return;
    }
  }
  std::size_t bad = 0;
  for (int z = 0; z < frame.res[2]; ++z) {
    for (int y = 0; y < frame.res[1]; ++y) {
      for (int x = 0; x < frame.res[0]; ++x) {
        const std::uint32_t c = frame.linear(x, y, z);
        for (std::uint32_t i = offsets[c]; i < offsets[c + 1]; ++i) {
          const std::uint32_t id = ids[i];
          if (id >= scene.primitive_count() || !scene.is_valid(id)) {
            problems.push_back("cell " + std::to_string(c) + " references invalid primitive " + std::to_string(id));
            continue;
          }
          seen[id] = 1;
          // The binning rule with twice the padding: rounding in the cell planes must not flag a correct reference.
          if (!primitive_overlaps_cell(scene, id, frame.cell_bounds(x, y, z), 2.0f * pad, exact) && bad++ < 5) {
            problems.push_back("primitive " + std::to_string(id) + " does not overlap its cell " + std::to_string(c));
          }
        }
      }
    }
  }
}

}  // namespace rayaccel
