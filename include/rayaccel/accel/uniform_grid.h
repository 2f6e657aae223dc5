// Uniform grid with compact cell lists (Lagae & Dutre 2008) and 3D-DDA traversal with mailboxing (Amanatides & Woo
// 1987); triangle cells are Triangle4 blocks. Also the binning helpers the two-level grid reuses.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/grid_dda.h"
#include "rayaccel/accel/option_table.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/accel/validation_report.h"
#include "rayaccel/geometry/ray_box.h"
#include "rayaccel/simd/dispatch.h"
#include "rayaccel/simd/triangle_blocks.h"

namespace rayaccel {

struct UniformGridOptions {
  /// Cells per axis ~ density * cbrt(n) for a cubic box (about density^3 cells per primitive). The default 3 is the
  /// classic rule (and this project's specification); with Triangle4 blocks fewer, fuller cells pay better
  /// (`grid:density=1,blocks=true,mailbox=false`: faster and a fraction of the memory). At density 3 blocks do not
  /// pay (memory grows for little gain), so they are off by default. Figures: BENCHMARKS.md, "Option choices".
  double density = 3.0;
  bool exact = true;  ///< triangles: drop references whose triangle misses the cell (SAT); others use boxes
  /// Skip primitives this ray tested in a recent cell; with blocks, a block whose triangles were all tested (with
  /// blocks the check costs more than it saves, see BENCHMARKS.md).
  bool mailbox = true;
  bool blocks = false;             ///< triangles: cells hold Triangle4 blocks tested with SIMD; else id lists
  int max_resolution = 1024;       ///< cells per axis at most
  std::uint64_t max_cells = 1u << 24;  ///< total cells at most (4 bytes each), bounds memory
};

/// Cells per axis for n primitives in a box of `extent`: total about density^3 * n, split in proportion to the
/// extent (cells_a = extent_a * cbrt(density^3 n / volume)); axes that would get less than one cell (flat scenes)
/// get one and the others share the budget. Each axis is clamped to [1, max_resolution] and the product to max_cells.
std::array<int, 3> grid_resolution(const Vec3& extent, std::size_t n, double density, int max_resolution,
                                   std::uint64_t max_cells);

/// (cell, primitive) pairs a grid level may hold for n primitives: `per_primitive` each plus 2^16. Well-spread
/// scenes use a few per primitive; many overlapping copies of one large triangle would otherwise each fill most of
/// the cells (5,000 identical triangles took minutes to bin).
inline std::size_t grid_reference_budget(std::size_t n, std::size_t per_primitive) {
  return per_primitive * n + (std::size_t(1) << 16);
}

/// Lowers a resolution over `box` (by 3/4 per axis per step) until binning `refs` by their boxes grown by `pad`
/// makes at most `budget` pairs, so a build's work and memory stay linear in its input.
std::array<int, 3> limit_references(std::array<int, 3> res, const AABB& box, std::span<const PrimRef> refs,
                                    float pad, std::size_t budget);

/// The cells per axis of one grid level over `box` holding `refs` (boxes grown by `pad`): grid_resolution(), then
/// limit_to_precision(), then limit_references() with grid_reference_budget(refs.size(), per_primitive). The one rule
/// for the uniform grid and both levels of the two-level grid.
std::array<int, 3> level_resolution(const AABB& box, std::span<const PrimRef> refs, float pad, double density,
                                    int max_resolution, std::uint64_t max_cells, std::size_t per_primitive);

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

/// The UniformGrid's options: key, member, range and doc of each (the registry's options, their parsing and checks).
const OptionTable<UniformGridOptions>& uniform_grid_option_table();

class UniformGrid final : public AcceleratorImpl<UniformGrid> {
 public:
  /// Throws Error naming the first option outside its range (uniform_grid_option_table()).
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
    simd::run_with_lanes<kMaxIsa>(isa_,
                         [&]<class Lanes>() RAYACCEL_LANE_LAMBDA { trace_cells<Lanes, AnyHit>(ray, hit, stats); });
  }

 private:
  template <class Lanes, bool AnyHit, class Stats>
  RAYACCEL_LANE_INLINE void trace_cells(const PreparedRay& ray, Hit& hit, Stats& stats) const;
  /// The id lists of every cell, from lists_ or, with blocks, read back from them.
  CellLists cell_lists() const;

  UniformGridOptions options_;
  const Scene* scene_ = nullptr;
  GridFrame frame_;
  float pad_ = 0.0f;
  bool exact_used_ = false;
  bool empty_ = true;
  bool test_all_ = false;  ///< the scene box is wider than float's range (grid_box_is_finite): no cells
  CellLists lists_;  ///< id lists; empty when the cells hold blocks
  /// With blocks: cell c holds blocks_[block_first_[c] .. block_first_[c + 1]).
  std::vector<std::uint32_t> block_first_;
  std::vector<simd::Triangle4> blocks_;
  std::vector<std::uint64_t> occupied_;  ///< bit c: cell c holds something
  /// Instruction set of the block tests (AVX2 at most: two blocks at a time; sse2: one, or no blocks at all).
  /// The widest kernels this structure runs: AVX2 (only bvh_wide has an AVX-512 build; the dispatch compiles no
  /// AVX-512 copy of this traversal).
  static constexpr simd::Isa kMaxIsa = simd::Isa::avx2;
  simd::Isa isa_ = simd::Isa::sse2;
  std::size_t references_ = 0;
  std::size_t prim_count_ = 0;
};

template <class Lanes, bool AnyHit, class Stats>
RAYACCEL_LANE_INLINE void UniformGrid::trace_cells(const PreparedRay& ray, Hit& hit, Stats& stats) const {
  if (empty_) return;
  float t0 = ray.t_min, t1 = ray.t_max;
  if (test_all_) {
    test_every_primitive<AnyHit>(*scene_, ray, hit, stats);
    return;
  }
  if (!clip_ray_to_box(ray, frame_.box, t0, t1)) return;
  GridDda dda(ray, frame_, t0);
  if (!dda.precise()) {
    test_every_primitive<AnyHit>(*scene_, ray, hit, stats);
    return;
  }
  RayMailbox<true> mailbox;
  simd::BlockMailbox block_mailbox;
  const simd::TrianglePacket<Lanes> packet(ray);
  const bool blocked = !block_first_.empty();
  const std::uint64_t* occupied = occupied_.data();
  for (;;) {
    stats.visit_node();
    const std::uint32_t c = frame_.linear(dda.cell(0), dda.cell(1), dda.cell(2));
    if ((occupied[c >> 6] >> (c & 63)) & 1u) {
      if (blocked) {
        const std::uint32_t first = block_first_[c];
        const std::uint32_t count = block_first_[c + 1] - first;
        const simd::Triangle4* blocks = blocks_.data() + first;
        const bool found =
            options_.mailbox
                ? simd::intersect_block_run<Lanes, AnyHit, true>(packet, ray, blocks, count, block_mailbox,
                                                                 hit, stats)
                : simd::intersect_block_run<Lanes, AnyHit, false>(packet, ray, blocks, count, block_mailbox,
                                                                  hit, stats);
        if (AnyHit && found) return;
      } else {
        const std::uint32_t* ids = lists_.ids.data();
        const std::uint32_t* begin = ids + lists_.offsets[c];
        const std::uint32_t* end = ids + lists_.offsets[c + 1];
        if (test_cell_primitives<AnyHit>(*scene_, begin, end, options_.mailbox, mailbox, ray, hit, stats)) return;
      }
    }
    if (hit.t <= dda.exit_t() || !dda.advance(ray, frame_)) return;
  }
}

void register_uniform_grid(std::vector<AcceleratorInfo>& registry);

}  // namespace rayaccel
