// Flattening an instanced scene: every instance's triangles mapped to world space in one triangle Scene, the
// reference two-level structures are compared against (tests/instance) and the baseline of their benchmarks.
#pragma once

#include <cstdint>
#include <vector>

#include "rayaccel/instance/instanced_scene.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {

struct FlattenedScene {
  Scene scene;
  /// first_prim[i]: the flat id of primitive 0 of instance i; instance i's primitive p is first_prim[i] + p.
  std::vector<std::uint64_t> first_prim;
  /// The instance a flat primitive id belongs to (binary search over first_prim).
  std::uint32_t instance_of(std::uint32_t flat_id) const;
};

/// Every instance's triangles, vertices mapped by its transform in double and rounded to the nearest float, in
/// instance order (primitive ids as in the geometry). Throws Error for a geometry that is not made of triangles or
/// a result of more than 2^32 - 1 triangles.
FlattenedScene flatten(const InstancedScene& scene);

}  // namespace rayaccel
