// Uniform grid: one regular grid over the scene with compact cell lists (Lagae & Dutre 2008, "Compact, Fast and
// Robust Grids for Ray Tracing"), resolution after Wald et al. / Ize et al., and 3D-DDA traversal with mailboxing
// (Amanatides & Woo 1987). Also declares the binning helpers the two-level grid reuses.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/grid_dda.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/geometry/ray_box.h"

namespace rayaccel {

struct UniformGridOptions {
  double density = 3.0;            ///< cells per axis ~ density * cbrt(n) for a cubic box (about density^3 cells per primitive)
  bool exact = true;               ///< triangles: drop references whose triangle misses the cell (SAT); others use boxes
  bool mailbox = true;             ///< skip primitives this ray tested in a recent cell
  int max_resolution = 1024;       ///< cells per axis at most
  std::uint64_t max_cells = 1u << 24;  ///< total cells at most (4 bytes each), bounds memory
};

/// Cells per axis for n primitives in a box of `extent`: total about density^3 * n, split in proportion to the
/// extent (cells_a = extent_a * cbrt(density^3 n / volume)); axes that would get less than one cell (flat scenes)
/// get one and the others share the budget. Each axis is clamped to [1, max_resolution] and the product to max_cells.
std::array<int, 3> grid_resolution(const Vec3& extent, std::size_t n, double density, int max_resolution,
                                   std::uint64_t max_cells);

/// Compact cell lists: the primitives of cell c are ids[offsets[c] .. offsets[c+1]).
struct CellLists {
  std::vector<std::uint32_t> offsets;
  std::vector<std::uint32_t> ids;
};

/// Assigns every reference to each cell of `frame` its box, grown by `pad`, touches; with `exact` and a triangle
/// scene, only to cells whose box grown by `pad` the triangle overlaps (triangle_overlaps_box). Within a cell, ids
/// keep the order of `refs`.
CellLists bin_primitives(const Scene& scene, std::span<const PrimRef> refs, const GridFrame& frame, float pad,
                         bool exact);

/// The binning rule for one primitive and one cell box (both before padding); validate() uses it.
bool primitive_overlaps_cell(const Scene& scene, std::uint32_t id, const AABB& cell, float pad, bool exact);

/// Checks the cell lists of one frame: `offsets` has cell_count + 1 monotone entries within `ids`; every id is a
/// valid primitive that overlaps its cell. Sets seen[id] for each referenced primitive; appends one line per
/// violation to `problems`.
void validate_cell_lists(const Scene& scene, std::span<const std::uint32_t> offsets,
                         std::span<const std::uint32_t> ids, const GridFrame& frame, float pad, bool exact,
                         std::vector<std::uint8_t>& seen, std::vector<std::string>& problems);

/// Appends a violation when a valid primitive of the scene has seen[id] == 0.
void check_all_referenced(const Scene& scene, const std::vector<std::uint8_t>& seen,
                          std::vector<std::string>& problems);

class UniformGrid final : public AcceleratorImpl<UniformGrid> {
 public:
  explicit UniformGrid(UniformGridOptions options = {});

  void build(const Scene& scene) override;
  std::size_t memory_bytes() const override;
  std::vector<BuildStatistic> build_statistics() const override;
  std::vector<std::string> validate() const override;

  const GridFrame& frame() const { return frame_; }

  /// Walks the cells the ray crosses front to back and stops once the closest hit lies in the current cell
  /// (hit.t <= cell exit); cells are padded at build time, so a hit just beyond the exit keeps the walk going.
  template <bool AnyHit, class Stats>
  void trace(const PreparedRay& ray, Hit& hit, Stats& stats) const {
    if (lists_.ids.empty()) return;
    float t0 = ray.t_min, t1 = ray.t_max;
    if (!clip_ray_to_box(ray, frame_.box, t0, t1)) return;
    GridDda dda(ray, frame_, t0);
    RayMailbox<true> mailbox;
    const std::uint32_t* ids = lists_.ids.data();
    for (;;) {
      stats.visit_node();
      const std::uint32_t c = frame_.linear(dda.cell(0), dda.cell(1), dda.cell(2));
      const std::uint32_t* begin = ids + lists_.offsets[c];
      const std::uint32_t* end = ids + lists_.offsets[c + 1];
      if (test_cell_primitives<AnyHit>(*scene_, begin, end, options_.mailbox, mailbox, ray, hit, stats)) return;
      if (hit.t <= dda.exit_t() || !dda.advance(ray, frame_)) return;
    }
  }

 private:
  UniformGridOptions options_;
  const Scene* scene_ = nullptr;
  GridFrame frame_;
  float pad_ = 0.0f;
  bool exact_used_ = false;
  CellLists lists_;
  std::size_t prim_count_ = 0;
};

void register_uniform_grid(std::vector<AcceleratorInfo>& registry);

}  // namespace rayaccel
