// Two-level grid (Kalojanov, Billeter, Slusallek 2011, "Two-Level Grids for Ray Tracing on GPUs"): a coarse top
// grid whose non-empty cells each hold a small uniform grid sized by their own primitive count, with compact cell
// lists at the second level. Both levels are walked by 3D-DDA; a hit inside the current leaf cell ends the walk.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/grid_dda.h"
#include "rayaccel/accel/option_table.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/geometry/ray_box.h"

namespace rayaccel {

struct TwoLevelGridOptions {
  double top_density = 1.0;        ///< top grid: about top_density^3 cells per primitive
  double leaf_density = 2.0;       ///< a top cell with k primitives gets about leaf_density^3 * k leaf cells
  bool exact = true;               ///< triangles: reference only cells the triangle overlaps (SAT)
  bool mailbox = true;             ///< skip primitives this ray tested in a recent cell
  int max_resolution = 512;        ///< top cells per axis at most
  std::uint64_t max_cells = 1u << 22;  ///< top cells at most
  int max_leaf_resolution = 128;   ///< leaf cells per axis of one top cell at most (<= 255)
};

/// The second level of one non-empty top cell.
struct SubGrid {
  AABB box;                  ///< 24 bytes: the top cell (padded) clipped to the box of its primitives
  std::uint32_t first_cell;  ///< 4 bytes: index of its first leaf cell in the leaf offset array
  std::uint8_t res[3];       ///< 3 bytes: leaf cells per axis
  std::uint8_t unused;       ///< 1 byte: padding
};
static_assert(sizeof(SubGrid) == 32, "SubGrid is 32 bytes");

/// The TwoLevelGrid's options: key, member, range and doc of each (the registry's options, their parsing and checks).
const OptionTable<TwoLevelGridOptions>& two_level_grid_option_table();

class TwoLevelGrid final : public AcceleratorImpl<TwoLevelGrid> {
 public:
  /// Throws Error naming the first option outside its range (two_level_grid_option_table()).
  explicit TwoLevelGrid(TwoLevelGridOptions options = {});

  void build(const Scene& scene) override;
  std::size_t memory_bytes() const override;
  std::vector<BuildStatistic> build_statistics() const override;
  std::vector<std::string> validate() const override;

  template <bool AnyHit, class Stats>
  void trace(const PreparedRay& ray, Hit& hit, Stats& stats) const {
    if (test_all_) {
      test_every_primitive<AnyHit>(*scene_, ray, hit, stats);
      return;
    }
    if (subgrids_.empty()) return;
    float t0 = ray.t_min, t1 = ray.t_max;
    if (!clip_ray_to_box(ray, top_.box, t0, t1)) return;
    GridDda top(ray, top_, t0);
    if (!top.precise()) {
      test_every_primitive<AnyHit>(*scene_, ray, hit, stats);
      return;
    }
    RayMailbox<true> mailbox;
    for (;;) {
      stats.visit_node();
      const std::uint32_t s = top_cells_[top_.linear(top.cell(0), top.cell(1), top.cell(2))];
      if (s != kEmptyCell && trace_subgrid<AnyHit>(subgrids_[s], ray, hit, mailbox, stats)) return;
      if (hit.t <= top.exit_t() || !top.advance(ray, top_)) return;
    }
  }

 private:
  static constexpr std::uint32_t kEmptyCell = 0xFFFFFFFFu;

  static GridFrame frame_of(const SubGrid& g) { return GridFrame::make(g.box, {g.res[0], g.res[1], g.res[2]}); }

  /// Walks one second-level grid; true when the whole trace may stop (any-hit found, or a hit in a leaf cell).
  template <bool AnyHit, class Stats>
  bool trace_subgrid(const SubGrid& g, const PreparedRay& ray, Hit& hit, RayMailbox<true>& mailbox, Stats& stats) const {
    float s0 = ray.t_min, s1 = hit.t;
    if (!clip_ray_to_box(ray, g.box, s0, s1)) return false;
    const GridFrame f = frame_of(g);
    GridDda dda(ray, f, s0);
    const std::uint32_t* ids = ids_.data();
    if (!dda.precise()) {  // every leaf cell of this subgrid, in any order
      const std::uint32_t cells = std::uint32_t(g.res[0]) * g.res[1] * g.res[2];
      for (std::uint32_t c = g.first_cell; c < g.first_cell + cells; ++c) {
        const std::uint32_t* begin = ids + leaf_offsets_[c];
        const std::uint32_t* end = ids + leaf_offsets_[c + 1];
        if (test_cell_primitives<AnyHit>(*scene_, begin, end, options_.mailbox, mailbox, ray, hit, stats)) return true;
      }
      return false;
    }
    for (;;) {
      stats.visit_node();
      const std::uint32_t c = g.first_cell + f.linear(dda.cell(0), dda.cell(1), dda.cell(2));
      const std::uint32_t* begin = ids + leaf_offsets_[c];
      const std::uint32_t* end = ids + leaf_offsets_[c + 1];
      if (test_cell_primitives<AnyHit>(*scene_, begin, end, options_.mailbox, mailbox, ray, hit, stats)) return true;
      if (hit.t <= dda.exit_t()) return true;
      if (!dda.advance(ray, f)) return false;
    }
  }

  TwoLevelGridOptions options_;
  const Scene* scene_ = nullptr;
  GridFrame top_;
  float pad_ = 0.0f;
  bool exact_used_ = false;
  bool test_all_ = false;  ///< the scene box is wider than float's range (grid_box_is_finite): no cells
  std::vector<std::uint32_t> top_cells_;     ///< per top cell: index into subgrids_, or kEmptyCell
  std::vector<SubGrid> subgrids_;
  std::vector<std::uint32_t> leaf_offsets_;  ///< all leaf cells of all subgrids, plus one end entry
  std::vector<std::uint32_t> ids_;
  std::size_t prim_count_ = 0;
};

void register_two_level_grid(std::vector<AcceleratorInfo>& registry);

}  // namespace rayaccel
