// Registry hook of the wide BVH (called by the built-in catalog, src/catalog/builtin_registry.cpp).
#pragma once

#include <vector>

#include "rayaccel/accel/registry.h"

namespace rayaccel::wide {

void register_wide_bvh(std::vector<AcceleratorInfo>& registry);

}  // namespace rayaccel::wide
