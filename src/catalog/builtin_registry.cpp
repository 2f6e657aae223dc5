// The catalog: the list of built-in structures, in the order `rayaccel list` shows them. Each module adds one line
// here; the one file of the library that includes every structure (the top layer, see scripts/check_layers.py).
#include "rayaccel/accel/brute_force.h"
#include "rayaccel/accel/default_spec.h"
#include "rayaccel/accel/bsp_tree.h"
#include "rayaccel/accel/kd_tree.h"
#include "rayaccel/accel/octree.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/accel/two_level_grid.h"
#include "rayaccel/accel/uniform_grid.h"
#include "rayaccel/wide/wide_bvh_registry.h"
#include "rayaccel/bvh/bvh_registry.h"

namespace rayaccel {

void register_builtin_accelerators(std::vector<AcceleratorInfo>& registry) {
  register_brute_force(registry);
  register_uniform_grid(registry);
  register_two_level_grid(registry);
  register_kd_tree(registry);
  register_octree(registry);
  register_bsp_tree(registry);
  register_bvh(registry);
  wide::register_wide_bvh(registry);
  // "embree", a comparison entry, is added by rayaccel::compare (enable_embree_comparison()), not here.
}

std::string default_accelerator_spec() { return "bvh_wide"; }  // the wide SIMD BVH

}  // namespace rayaccel
