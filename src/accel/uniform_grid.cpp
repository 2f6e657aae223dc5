// Uniform grid: build over the padded scene box, validation, statistics and registration (see uniform_grid.h).
#include "rayaccel/accel/uniform_grid.h"

#include <cmath>
#include <memory>

#include "rayaccel/core/error.h"

namespace rayaccel {

namespace {

void check_options(const UniformGridOptions& o) {
  if (!(o.density > 0.0) || !std::isfinite(o.density)) {
    throw Error("grid: density must be a positive number, got " + std::to_string(o.density));
  }
  if (o.max_resolution < 1 || o.max_resolution > 65536) {
    throw Error("grid: max_resolution must be in [1, 65536], got " + std::to_string(o.max_resolution));
  }
  if (o.max_cells < 1 || o.max_cells > (1ull << 31)) {
    throw Error("grid: max_cells must be in [1, 2^31], got " + std::to_string(o.max_cells));
  }
}

}  // namespace

UniformGrid::UniformGrid(UniformGridOptions options) : options_(options) { check_options(options_); }

void UniformGrid::build(const Scene& scene) {
  scene_ = &scene;
  const std::vector<PrimRef> refs = scene.build_references();
  prim_count_ = refs.size();
  exact_used_ = options_.exact && scene.kind() == PrimitiveKind::triangles;
  lists_ = {};
  if (refs.empty()) {
    frame_ = GridFrame::make(AABB({0, 0, 0}, {1, 1, 1}), {1, 1, 1});
    lists_.offsets.assign(2, 0);
    return;
  }
  const AABB box = padded_scene_box(scene.bounds());
  frame_ = GridFrame::make(box, limit_to_precision(grid_resolution(box.extent(), refs.size(), options_.density,
                                                                   options_.max_resolution, options_.max_cells),
                                                   box));
  pad_ = cell_padding(box);
  lists_ = bin_primitives(scene, refs, frame_, pad_, exact_used_);
}

std::size_t UniformGrid::memory_bytes() const {
  return lists_.offsets.capacity() * sizeof(std::uint32_t) + lists_.ids.capacity() * sizeof(std::uint32_t) +
         sizeof(*this);
}

std::vector<BuildStatistic> UniformGrid::build_statistics() const {
  std::size_t empty = 0;
  for (std::size_t c = 0; c + 1 < lists_.offsets.size(); ++c) empty += lists_.offsets[c] == lists_.offsets[c + 1];
  const double cells = frame_.cell_count();
  return {{"resolution_x", double(frame_.res[0])},
          {"resolution_y", double(frame_.res[1])},
          {"resolution_z", double(frame_.res[2])},
          {"cells", cells},
          {"empty_cell_fraction", cells > 0 ? double(empty) / cells : 0.0},
          {"references", double(lists_.ids.size())},
          {"references_per_primitive", prim_count_ ? double(lists_.ids.size()) / double(prim_count_) : 0.0}};
}

std::vector<std::string> UniformGrid::validate() const {
  if (!scene_) return {"not built"};
  std::vector<std::string> problems;
  std::vector<std::uint8_t> seen(scene_->primitive_count(), 0);
  if (lists_.offsets.empty() || lists_.offsets.front() != 0 || lists_.offsets.back() != lists_.ids.size()) {
    problems.push_back("offsets do not span the reference array exactly");
    return problems;
  }
  validate_cell_lists(*scene_, lists_.offsets, lists_.ids, frame_, pad_, exact_used_, seen, problems);
  check_all_referenced(*scene_, seen, problems);
  if (prim_count_ > 0 && !frame_.box.contains(scene_->bounds())) problems.push_back("grid box does not hold the scene");
  return problems;
}

void register_uniform_grid(std::vector<AcceleratorInfo>& registry) {
  const UniformGridOptions d;
  registry.push_back(
      {"grid",
       "uniform grid with compact cell lists and 3D-DDA traversal (Amanatides & Woo 1987, Lagae & Dutre 2008)",
       {{"density", OptionType::real, "3", "cells per axis ~ density * cbrt(primitives)", {}},
        {"exact", OptionType::boolean, "true", "triangles: reference only cells the triangle overlaps (SAT)", {}},
        {"mailbox", OptionType::boolean, "true", "test a primitive spanning cells once per ray", {}},
        {"max_resolution", OptionType::integer, std::to_string(d.max_resolution), "cells per axis at most", {}},
        {"max_cells", OptionType::integer, std::to_string(d.max_cells), "total cells at most (bounds memory)", {}}},
       {"grid", "grid:exact=false", "grid:mailbox=false"},
       [](const Options& o) {
         UniformGridOptions opt;
         opt.density = o.get_real("density");
         opt.exact = o.get_bool("exact");
         opt.mailbox = o.get_bool("mailbox");
         const long long res = o.get_int("max_resolution");
         const long long cells = o.get_int("max_cells");
         if (res < 1 || res > 65536) throw Error("grid: max_resolution must be in [1, 65536], got " + std::to_string(res));
         if (cells < 1) throw Error("grid: max_cells must be at least 1, got " + std::to_string(cells));
         opt.max_resolution = int(res);
         opt.max_cells = std::uint64_t(cells);
         return std::make_unique<UniformGrid>(opt);
       }});
}

}  // namespace rayaccel
