// Two-level grid build (Kalojanov et al. 2011): bin into the top grid, then give each non-empty top cell its own
// grid over the part of the cell its primitives occupy; validation, statistics and registration.
#include "rayaccel/accel/two_level_grid.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "rayaccel/accel/uniform_grid.h"
#include "rayaccel/core/error.h"

namespace rayaccel {

namespace {

AABB grow(const AABB& b, float pad) { return {b.lo - Vec3{pad}, b.hi + Vec3{pad}}; }

}  // namespace

const OptionTable<TwoLevelGridOptions>& two_level_grid_option_table() {
  using O = TwoLevelGridOptions;
  static const OptionTable<O> table = [] {
    OptionTable<O> t("grid2");
    t.real("top_density", &O::top_density, RealRange::positive(), "top cells per axis ~ top_density * cbrt(primitives)");
    t.real("leaf_density", &O::leaf_density, RealRange::positive(),
           "leaf cells per axis of a top cell ~ leaf_density * cbrt(its primitives)");
    t.boolean("exact", &O::exact, "triangles: reference only cells the triangle overlaps (SAT)");
    t.boolean("mailbox", &O::mailbox, "test a primitive spanning cells once per ray");
    t.integer("max_resolution", &O::max_resolution, 1, 65536, "top cells per axis at most");
    t.integer("max_cells", &O::max_cells, 1, 1ll << 31, "top cells at most");
    t.integer("max_leaf_resolution", &O::max_leaf_resolution, 1, 255, "leaf cells per axis in one top cell at most");
    return t;
  }();
  return table;
}

TwoLevelGrid::TwoLevelGrid(TwoLevelGridOptions options) : options_(options) {
  two_level_grid_option_table().check(options_);
}

void TwoLevelGrid::build(const Scene& scene) {
  scene_ = &scene;
  const PrimRefs refs = scene.build_references();
  prim_count_ = refs.size();
  exact_used_ = options_.exact && scene.kind() == PrimitiveKind::triangles;
  top_cells_.clear();
  subgrids_.clear();
  leaf_offsets_.assign(1, 0);
  ids_.clear();
  const AABB box = padded_scene_box(scene.bounds());
  test_all_ = !refs.empty() && !grid_box_is_finite(box);
  if (refs.empty() || test_all_) {
    top_ = GridFrame::make(AABB({0, 0, 0}, {1, 1, 1}), {1, 1, 1});
    top_cells_.assign(1, kEmptyCell);
    return;
  }
  pad_ = cell_padding(box);
  top_ = GridFrame::make(
      box, level_resolution(box, refs, pad_, options_.top_density, options_.max_resolution, options_.max_cells, 16));
  const CellLists top_lists = bin_primitives(scene, refs, top_, pad_, exact_used_);

  // Second level, one independent grid per non-empty top cell, built in parallel.
  std::vector<std::uint32_t> occupied;
  for (std::uint32_t c = 0; c < top_.cell_count(); ++c) {
    if (top_lists.offsets[c] != top_lists.offsets[c + 1]) occupied.push_back(c);
  }
  std::vector<SubGrid> grids(occupied.size());
  std::vector<CellLists> lists(occupied.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, occupied.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const std::uint32_t c = occupied[i];
      const int x = int(c % std::uint32_t(top_.res[0]));
      const int y = int((c / std::uint32_t(top_.res[0])) % std::uint32_t(top_.res[1]));
      const int z = int(c / (std::uint32_t(top_.res[0]) * std::uint32_t(top_.res[1])));
      PrimRefs cell_refs;
      AABB content;
      for (std::uint32_t k = top_lists.offsets[c]; k < top_lists.offsets[c + 1]; ++k) {
        const std::uint32_t id = top_lists.ids[k];
        cell_refs.push_back({scene.primitive_bounds(id), id});
        content.extend(scene.primitive_bounds(id));
      }
      AABB sub = intersection(grow(top_.cell_bounds(x, y, z), pad_), grow(content, pad_));
      for (int a = 0; a < 3; ++a) {
        if (!(sub.hi[a] - sub.lo[a] >= pad_)) { sub.lo[a] -= pad_; sub.hi[a] += pad_; }
      }
      const auto res =
          level_resolution(sub, cell_refs, pad_, options_.leaf_density, options_.max_leaf_resolution, 1u << 21, 64);
      SubGrid& g = grids[i];
      g.box = sub;
      g.first_cell = 0;
      for (int a = 0; a < 3; ++a) g.res[a] = std::uint8_t(res[a]);
      g.unused = 0;
      lists[i] = bin_primitives(scene, cell_refs, frame_of(g), pad_, exact_used_);
    }
  });

  // Assemble: leaf offsets of every subgrid in one array, references in one array.
  top_cells_.assign(top_.cell_count(), kEmptyCell);
  std::size_t leaf_cells = 0, references = 0;
  for (std::size_t i = 0; i < grids.size(); ++i) {
    leaf_cells += lists[i].offsets.size() - 1;
    references += lists[i].ids.size();
  }
  leaf_offsets_.clear();
  leaf_offsets_.reserve(leaf_cells + 1);
  ids_.reserve(references);
  for (std::size_t i = 0; i < grids.size(); ++i) {
    grids[i].first_cell = std::uint32_t(leaf_offsets_.size());
    const auto base = std::uint32_t(ids_.size());
    for (std::size_t c = 0; c + 1 < lists[i].offsets.size(); ++c) leaf_offsets_.push_back(base + lists[i].offsets[c]);
    ids_.insert(ids_.end(), lists[i].ids.begin(), lists[i].ids.end());
    top_cells_[occupied[i]] = std::uint32_t(i);
  }
  leaf_offsets_.push_back(std::uint32_t(ids_.size()));
  subgrids_ = std::move(grids);
}

std::size_t TwoLevelGrid::memory_bytes() const {
  return top_cells_.capacity() * sizeof(std::uint32_t) + subgrids_.capacity() * sizeof(SubGrid) +
         leaf_offsets_.capacity() * sizeof(std::uint32_t) + ids_.capacity() * sizeof(std::uint32_t) + sizeof(*this);
}

std::vector<BuildStatistic> TwoLevelGrid::build_statistics() const {
  std::size_t empty = 0;
  for (std::size_t c = 0; c + 1 < leaf_offsets_.size(); ++c) empty += leaf_offsets_[c] == leaf_offsets_[c + 1];
  const double leaves = double(leaf_offsets_.size() - 1);
  return {{"top_resolution_x", double(top_.res[0])},
          {"top_resolution_y", double(top_.res[1])},
          {"top_resolution_z", double(top_.res[2])},
          {"top_cells", double(top_.cell_count())},
          {"occupied_top_cells", double(subgrids_.size())},
          {"leaf_cells", leaves},
          {"empty_leaf_fraction", leaves > 0 ? double(empty) / leaves : 0.0},
          {"references", double(ids_.size())},
          {"references_per_primitive", prim_count_ ? double(ids_.size()) / double(prim_count_) : 0.0},
          {"tests_every_primitive", test_all_ ? 1.0 : 0.0}};
}

std::vector<std::string> TwoLevelGrid::validate() const {
  if (!scene_) return {"not built"};
  if (test_all_) return {};  // no cells: every ray tests every primitive
  std::vector<std::string> problems;
  if (top_cells_.size() != top_.cell_count()) problems.push_back("top cell array does not match the top resolution");
  if (leaf_offsets_.empty() || leaf_offsets_.front() != 0 || leaf_offsets_.back() != ids_.size()) {
    problems.push_back("leaf offsets do not span the reference array exactly");
  }
  if (!problems.empty()) return problems;
  std::vector<std::uint8_t> seen(scene_->primitive_count(), 0), used(subgrids_.size(), 0);
  std::uint32_t next_cell = 0;
  for (int z = 0; z < top_.res[2]; ++z) {
    for (int y = 0; y < top_.res[1]; ++y) {
      for (int x = 0; x < top_.res[0]; ++x) {
        const std::uint32_t s = top_cells_[top_.linear(x, y, z)];
        if (s == kEmptyCell) continue;
        if (s >= subgrids_.size() || used[s]) {
          problems.push_back("top cell " + std::to_string(top_.linear(x, y, z)) + " has a bad or shared subgrid");
          continue;
        }
        used[s] = 1;
        const SubGrid& g = subgrids_[s];
        const GridFrame f = frame_of(g);
        if (g.first_cell != next_cell) problems.push_back("subgrid " + std::to_string(s) + " leaf cells are not packed");
        next_cell = g.first_cell + f.cell_count();
        if (!grow(top_.cell_bounds(x, y, z), 2.0f * pad_).contains(g.box)) {
          problems.push_back("subgrid " + std::to_string(s) + " box leaves its top cell");
        }
        if (std::size_t(g.first_cell) + f.cell_count() + 1 > leaf_offsets_.size()) {
          problems.push_back("subgrid " + std::to_string(s) + " leaf cells run past the offset array");
          continue;
        }
        validate_cell_lists(*scene_, std::span(leaf_offsets_).subspan(g.first_cell, f.cell_count() + 1), ids_, f,
                            pad_, exact_used_, seen, problems);
      }
    }
  }
  if (next_cell + 1 != leaf_offsets_.size()) problems.push_back("leaf offset array has cells no subgrid owns");
  report_unreferenced(*scene_, seen, "cell", problems);
  return problems;
}

void register_two_level_grid(std::vector<AcceleratorInfo>& registry) {
  registry.push_back(registry_entry<TwoLevelGrid>(
      two_level_grid_option_table(),
      "two-level grid: a coarse grid whose occupied cells hold their own grids (Kalojanov et al. 2011)",
      {"grid2", "grid2:exact=false"}));
}

}  // namespace rayaccel
