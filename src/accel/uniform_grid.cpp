// Uniform grid: build over the padded scene box, the Triangle4 copy of the cells, validation, statistics and
// registration (see uniform_grid.h).
#include "rayaccel/accel/uniform_grid.h"

#include <cmath>
#include <memory>

#include "rayaccel/core/error.h"

namespace rayaccel {

const OptionTable<UniformGridOptions>& uniform_grid_option_table() {
  using O = UniformGridOptions;
  static const OptionTable<O> table = [] {
    OptionTable<O> t("grid");
    t.real("density", &O::density, RealRange::positive(), "cells per axis ~ density * cbrt(primitives)");
    t.boolean("exact", &O::exact, "triangles: reference only cells the triangle overlaps (SAT)");
    t.boolean("mailbox", &O::mailbox, "test a primitive spanning cells once per ray (blocks: whole blocks)");
    t.boolean("blocks", &O::blocks, "triangles: cells hold Triangle4 blocks tested with SIMD (pays at density 1)");
    t.integer("max_resolution", &O::max_resolution, 1, 65536, "cells per axis at most");
    t.integer("max_cells", &O::max_cells, 1, 1ll << 31, "total cells at most (bounds memory)");
    return t;
  }();
  return table;
}

UniformGrid::UniformGrid(UniformGridOptions options) : options_(options) { uniform_grid_option_table().check(options_); }

void UniformGrid::build(const Scene& scene) {
  scene_ = &scene;
  const PrimRefs refs = scene.build_references();
  prim_count_ = refs.size();
  exact_used_ = options_.exact && scene.kind() == PrimitiveKind::triangles;
  lists_ = {};
  block_first_ = {};
  blocks_ = {};
  occupied_ = {};
  references_ = 0;
  isa_ = simd::Isa::sse2;
  empty_ = refs.empty();
  const AABB box = padded_scene_box(scene.bounds());
  test_all_ = !empty_ && !grid_box_is_finite(box);
  if (empty_ || test_all_) {
    frame_ = GridFrame::make(AABB({0, 0, 0}, {1, 1, 1}), {1, 1, 1});
    lists_.offsets.assign(2, 0);
    occupied_.assign(1, 0);
    return;
  }
  pad_ = cell_padding(box);
  frame_ = GridFrame::make(
      box, level_resolution(box, refs, pad_, options_.density, options_.max_resolution, options_.max_cells, 64));
  lists_ = bin_primitives(scene, refs, frame_, pad_, exact_used_);
  references_ = lists_.ids.size();
  const std::uint32_t cells = frame_.cell_count();
  occupied_.assign((std::size_t(cells) + 63) / 64, 0);
  for (std::uint32_t c = 0; c < cells; ++c) {
    if (lists_.offsets[c] != lists_.offsets[c + 1]) occupied_[c >> 6] |= std::uint64_t(1) << (c & 63);
  }
  if (!options_.blocks || scene.kind() != PrimitiveKind::triangles) return;
  // Each cell's list becomes a run of Triangle4 blocks; the id lists are dropped (validate() reads the blocks back).
  block_first_.resize(std::size_t(cells) + 1);
  for (std::uint32_t c = 0; c < cells; ++c) {
    block_first_[c] = static_cast<std::uint32_t>(blocks_.size());
    const std::uint32_t first = lists_.offsets[c], last = lists_.offsets[c + 1];
    simd::pack_triangle_blocks(
        scene, std::span<const std::uint32_t>(lists_.ids.data() + first, last - first), blocks_);
    if (block_first_[c] == blocks_.size()) occupied_[c >> 6] &= ~(std::uint64_t(1) << (c & 63));
  }
  block_first_.back() = static_cast<std::uint32_t>(blocks_.size());
  blocks_.shrink_to_fit();
  lists_ = {};
  isa_ = simd::best_isa(kMaxIsa);
}

CellLists UniformGrid::cell_lists() const {
  if (block_first_.empty()) return lists_;
  CellLists out;
  out.offsets.reserve(block_first_.size());
  for (std::size_t c = 0; c + 1 < block_first_.size(); ++c) {
    out.offsets.push_back(static_cast<std::uint32_t>(out.ids.size()));
    simd::for_each_block_id(blocks_.data() + block_first_[c], block_first_[c + 1] - block_first_[c],
                            [&](const simd::Triangle4& b, int lane) { out.ids.push_back(b.prim_id[lane]); });
  }
  out.offsets.push_back(static_cast<std::uint32_t>(out.ids.size()));
  return out;
}

std::size_t UniformGrid::memory_bytes() const {
  return lists_.offsets.capacity() * sizeof(std::uint32_t) + lists_.ids.capacity() * sizeof(std::uint32_t) +
         block_first_.capacity() * sizeof(std::uint32_t) + blocks_.capacity() * sizeof(simd::Triangle4) +
         occupied_.capacity() * sizeof(std::uint64_t) + sizeof(*this);
}

std::vector<BuildStatistic> UniformGrid::build_statistics() const {
  std::size_t empty = 0;
  for (std::uint32_t c = 0; c < frame_.cell_count(); ++c) empty += empty_ || !((occupied_[c >> 6] >> (c & 63)) & 1u);
  const double cells = frame_.cell_count();
  std::vector<BuildStatistic> stats = {
      {"resolution_x", double(frame_.res[0])},
      {"resolution_y", double(frame_.res[1])},
      {"resolution_z", double(frame_.res[2])},
      {"cells", cells},
      {"empty_cell_fraction", cells > 0 ? double(empty) / cells : 0.0},
      {"references", double(references_)},
      {"references_per_primitive", prim_count_ ? double(references_) / double(prim_count_) : 0.0},
      {"tests_every_primitive", test_all_ ? 1.0 : 0.0}};
  if (!block_first_.empty()) {
    std::size_t used = 0;
    for (const auto& b : blocks_) {
      for (std::uint32_t id : b.prim_id) used += id != kInvalidPrimId ? 1 : 0;
    }
    stats.push_back({"triangle4_blocks", double(blocks_.size())});
    stats.push_back({"block_fill", blocks_.empty() ? 0.0 : double(used) / (4.0 * double(blocks_.size()))});
  }
  return stats;
}

std::vector<std::string> UniformGrid::validate() const {
  if (!scene_) return {"not built"};
  if (test_all_) return {};  // no cells: every ray tests every primitive
  std::vector<std::string> problems;
  std::vector<std::uint8_t> seen(scene_->primitive_count(), 0);
  const CellLists lists = cell_lists();
  if (lists.offsets.empty() || lists.offsets.front() != 0 || lists.offsets.back() != lists.ids.size()) {
    problems.push_back("offsets do not span the reference array exactly");
    return problems;
  }
  validate_cell_lists(*scene_, lists.offsets, lists.ids, frame_, pad_, exact_used_, seen, problems);
  if (!empty_ && occupied_.size() != (std::size_t(frame_.cell_count()) + 63) / 64) {
    problems.push_back("occupancy bits do not match the cells");
  } else if (!empty_) {
    for (std::uint32_t c = 0; c < frame_.cell_count(); ++c) {
      const bool bit = (occupied_[c >> 6] >> (c & 63)) & 1u;
      if (bit != (lists.offsets[c] != lists.offsets[c + 1])) {
        problems.push_back("occupancy bit of cell " + std::to_string(c) + " is wrong");
        break;
      }
    }
  }
  if (const auto stale = simd::first_stale_lane(blocks_, *scene_)) {
    problems.push_back("block copy of triangle " + std::to_string(*stale) + " differs from the scene");
    return problems;
  }
  report_unreferenced(*scene_, seen, "cell", problems);
  if (prim_count_ > 0 && !frame_.box.contains(scene_->bounds())) problems.push_back("grid box does not hold the scene");
  return problems;
}

void register_uniform_grid(std::vector<AcceleratorInfo>& registry) {
  registry.push_back(registry_entry<UniformGrid>(
      uniform_grid_option_table(),
      "uniform grid with compact cell lists and 3D-DDA traversal (Amanatides & Woo 1987, Lagae & Dutre 2008)",
      {"grid", "grid:exact=false", "grid:mailbox=false", "grid:density=1,blocks=true,mailbox=false",
        "grid:density=1,blocks=true,mailbox=true"}));
}

}  // namespace rayaccel
