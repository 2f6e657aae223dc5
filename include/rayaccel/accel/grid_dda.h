// Shared pieces of the spatial subdivisions (uniform grid, two-level grid, octree): the geometry of a regular grid,
// incremental 3D-DDA stepping (Amanatides & Woo 1987, "A Fast Voxel Traversal Algorithm for Ray Tracing") and the
// per-cell primitive loop with the shared per-ray mailbox (RayMailbox, ray_mailbox.h).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "rayaccel/accel/leaf_test.h"
#include "rayaccel/accel/ray_mailbox.h"
#include "rayaccel/core/aabb.h"
#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {

/// Relative margin by which primitives are padded when assigned to cells: far above float rounding of the cell
/// planes and of the DDA's distances, so a primitive within rounding distance of a cell boundary (or lying in it)
/// is referenced on both sides and a ray running along a boundary finds it in whichever cell it is stepped through.
inline float cell_padding(const AABB& box) {
  const Vec3 mag = max(abs(box.lo), abs(box.hi));
  return max_component(mag) * 0x1p-18f + max_component(box.extent()) * 0x1p-20f;
}

/// The smallest cell edge worth having in `box`: 2^-16 of its largest coordinate magnitude (about 128 float ulps,
/// four times cell_padding()). Finer cells cannot be told apart in float (a soup 1e8 across at 1e15 would
/// otherwise get cells smaller than the spacing of its own coordinates, each padded over all of its neighbours).
inline float min_cell_size(const AABB& box) { return max_component(max(abs(box.lo), abs(box.hi))) * 0x1p-16f; }

/// Lowers a per-axis resolution so no cell is smaller than min_cell_size(box).
inline std::array<int, 3> limit_to_precision(std::array<int, 3> res, const AABB& box) {
  const float min_size = min_cell_size(box);
  for (int a = 0; a < 3; ++a) {
    const float most = std::floor((box.hi[a] - box.lo[a]) / min_size);
    if (most < float(res[a])) res[a] = std::max(1, int(most));
  }
  return res;
}

/// True when a grid can be laid over `box` in float: its corners and its extent are finite. A scene wider than
/// float's range (vertices at +-2e38) fails; the grids then test every primitive for each ray instead of walking
/// cells whose planes, sizes and distances would overflow.
inline bool grid_box_is_finite(const AABB& box) {
  return is_finite(box.lo) && is_finite(box.hi) && is_finite(box.hi - box.lo);
}

/// The scene box padded so that every axis has a positive extent (flat scenes still get a valid grid).
inline AABB padded_scene_box(const AABB& bounds) {
  const float pad = std::max({max_component(bounds.extent()) * 0x1p-10f,
                              max_component(max(abs(bounds.lo), abs(bounds.hi))) * 0x1p-18f, 1e-30f});
  return {bounds.lo - Vec3{pad}, bounds.hi + Vec3{pad}};
}

/// A regular grid of res[0] x res[1] x res[2] cells over `box`. Cell planes are lo + k * cell_size, except the last
/// plane, which is box.hi exactly; build and traversal both use plane(), so they agree on every boundary.
struct GridFrame {
  AABB box;
  std::array<int, 3> res{1, 1, 1};
  Vec3 cell_size;
  Vec3 inv_cell_size;

  static GridFrame make(const AABB& box, const std::array<int, 3>& res) {
    GridFrame f;
    f.box = box;
    f.res = res;
    for (int a = 0; a < 3; ++a) {
      f.cell_size[a] = (box.hi[a] - box.lo[a]) / float(res[a]);
      f.inv_cell_size[a] = float(res[a]) / (box.hi[a] - box.lo[a]);
    }
    return f;
  }
  std::uint32_t cell_count() const { return std::uint32_t(res[0]) * std::uint32_t(res[1]) * std::uint32_t(res[2]); }
  std::uint32_t linear(int x, int y, int z) const {
    return (std::uint32_t(z) * std::uint32_t(res[1]) + std::uint32_t(y)) * std::uint32_t(res[0]) + std::uint32_t(x);
  }
  float plane(int axis, int k) const { return k >= res[axis] ? box.hi[axis] : box.lo[axis] + float(k) * cell_size[axis]; }
  /// The cell holding coordinate `coord` on `axis`, clamped into the grid. A NaN position (0 * inf on an axis where
  /// the box is flat, which has the one cell 0) reads as cell 0.
  int cell_of(float coord, int axis) const {
    const float f = (coord - box.lo[axis]) * inv_cell_size[axis];
    return f > 0.0f ? int(std::min(f, float(res[axis] - 1))) : 0;
  }
  AABB cell_bounds(int x, int y, int z) const {
    return {{plane(0, x), plane(1, y), plane(2, z)}, {plane(0, x + 1), plane(1, y + 1), plane(2, z + 1)}};
  }
};

/// Where a subdivision's traversal starts along a ray that enters its box at t_enter (t_min, or an entry clipped to
/// the box): a distance t_base no later than the ray's true entry and the ray's point there, computed in double and
/// rounded once. Traversal geometry measured from that point (plane distances, cell indices) keeps the precision of
/// the structure's own coordinates instead of that of a far origin: from an origin 1e6 box sizes away, float
/// distances measured from the origin are off by more than a cell. A clipped entry is recomputed in double and moved
/// back by 2^-40 of itself (its rounding is below 2^-50). When even that margin exceeds the box (origins more than
/// about 1e12 box sizes away), `precise` is false and the caller tests every primitive it holds instead.
struct TraversalStart {
  double t_base = 0.0;
  Vec3 origin;
  bool shifted = false;
  /// False when the origin is too far for any start to be measured precisely: the caller then tests every primitive
  /// it holds instead of walking its cells (a float ray from 1e12 box sizes away cannot resolve the cells anyway).
  bool precise = true;

  TraversalStart(const PreparedRay& r, const AABB& box, float t_enter) : origin(r.origin) {
    double t = t_enter;
    double back = 0.0;  // how far the start lies before the entry, in t
    if (t_enter > r.t_min) {
      t = r.t_min;
      for (int a = 0; a < 3; ++a) {
        if (r.direction[a] == 0.0f || !std::isfinite(r.inv_direction[a])) continue;
        const double near_plane = r.negative[a] ? box.hi[a] : box.lo[a];
        t = std::max(t, (near_plane - double(r.origin[a])) / double(r.direction[a]));
      }
      back = std::fabs(t) * 0x1p-40;
      t -= back;
    }
    if (t == 0.0) return;
    // The start's distance from the box (back) and its rounding in double must stay well within the box.
    const double d_max = max_component(abs(r.direction));
    const double error = 0x1p-52 * (double(max_component(abs(r.origin))) + d_max * std::fabs(t));
    if (!((back * d_max + error) <= double(max_component(box.extent())))) {
      precise = false;
      return;
    }
    t_base = t;
    shifted = true;
    for (int a = 0; a < 3; ++a) origin[a] = static_cast<float>(double(r.origin[a]) + double(r.direction[a]) * t);
  }
  /// A distance measured from the start, as a distance along the ray.
  float absolute(float local_t) const { return shifted ? static_cast<float>(t_base + double(local_t)) : local_t; }
};

/// Incremental 3D-DDA over a GridFrame. Distances to the next planes are recomputed from plane() at each step (not
/// accumulated) and measured from the traversal start (TraversalStart), so they carry only a few roundings of the
/// grid's own scale however long the walk and however far the origin. Zero direction components (+0 and -0, and
/// subnormals whose reciprocal overflows) never step on their axis.
class GridDda {
 public:
  /// Starts in the cell holding the traversal start for t_enter (clamped into the grid).
  GridDda(const PreparedRay& r, const GridFrame& g, float t_enter) : start_(r, g.box, t_enter) {
    const Vec3 p = start_.shifted ? start_.origin : r.origin + r.direction * t_enter;
    for (int a = 0; a < 3; ++a) {
      cell_[a] = g.cell_of(p[a], a);
      const bool moves = r.direction[a] != 0.0f && std::isfinite(r.inv_direction[a]);
      step_[a] = !moves ? 0 : (r.direction[a] > 0.0f ? 1 : -1);
      end_[a] = step_[a] > 0 ? g.res[a] : -1;
      t_next_[a] = step_[a] == 0 ? std::numeric_limits<float>::infinity() : next_plane_t(r, g, a);
    }
  }

  /// See TraversalStart::precise: when false, the caller must not rely on the walk.
  bool precise() const { return start_.precise; }
  int cell(int axis) const { return cell_[axis]; }
  /// Distance at which the ray leaves the current cell.
  float exit_t() const { return start_.absolute(std::min({t_next_[0], t_next_[1], t_next_[2]})); }
  /// Moves to the next cell along the ray; false when the ray leaves the grid.
  bool advance(const PreparedRay& r, const GridFrame& g) {
    const int a = t_next_[0] <= t_next_[1] ? (t_next_[0] <= t_next_[2] ? 0 : 2) : (t_next_[1] <= t_next_[2] ? 1 : 2);
    if (step_[a] == 0) return false;  // every axis at +inf: the ray never leaves this cell
    cell_[a] += step_[a];
    if (cell_[a] == end_[a]) return false;
    t_next_[a] = next_plane_t(r, g, a);
    return true;
  }

 private:
  /// Distance from the traversal start to the cell's next plane on axis a.
  float next_plane_t(const PreparedRay& r, const GridFrame& g, int a) const {
    return (g.plane(a, cell_[a] + (step_[a] > 0 ? 1 : 0)) - start_.origin[a]) * r.inv_direction[a];
  }

  TraversalStart start_;
  int cell_[3];
  int step_[3];
  int end_[3];
  float t_next_[3];  ///< measured from the traversal start
};

/// Tests every valid primitive of the scene: the traversal of a grid over all of them when TraversalStart is not
/// precise.
template <bool AnyHit, class Stats>
inline void test_every_primitive(const Scene& scene, const PreparedRay& ray, Hit& hit, Stats& stats) {
  for (std::uint32_t id = 0; id < scene.primitive_count(); ++id) {
    if (!scene.is_valid(id)) continue;
    if (test_scene_primitive(scene, id, ray, hit, stats) && AnyHit) return;
  }
}

/// Tests the primitives [begin, end) of one cell, skipping mailboxed ones when `use_mailbox`. Returns true when an
/// any-hit query may stop.
template <bool AnyHit, class Stats>
inline bool test_cell_primitives(const Scene& scene, const std::uint32_t* begin, const std::uint32_t* end,
                                 bool use_mailbox, RayMailbox<true>& mailbox, const PreparedRay& ray, Hit& hit,
                                 Stats& stats) {
  for (const std::uint32_t* p = begin; p != end; ++p) {
    if (use_mailbox && mailbox.seen_before(*p)) continue;
    if (test_scene_primitive(scene, *p, ray, hit, stats) && AnyHit) return true;
  }
  return false;
}

}  // namespace rayaccel
