// Triangle pre-splitting (Karras & Aila 2013; Ernst & Greiner 2007): large or badly fitting triangles cut at the
// coarsest grid planes into several references before an object-split build (the algorithm: docs/design.md).
#pragma once

#include <cstdint>
#include <vector>

#include "rayaccel/core/primitives.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {

struct PresplitOptions {
  /// Extra references allowed, as a fraction of the number of valid triangles (0 = no splitting).
  float fraction = 0.3f;
  /// Exponent Y of the priority (Karras & Aila use 1/3: flattens the priority so more triangles get a split).
  float priority_exponent = 1.0f / 3.0f;
};

struct PresplitResult {
  PrimRefs refs;  ///< one per valid triangle in id order (its first piece if split), then the further pieces
  std::uint32_t split_triangles = 0;   ///< triangles cut into two or more pieces
};

/// How much pre-splitting can gain on `scene`: the sum over its valid triangles of 2^-d (A_box - A_ideal) (the
/// quantity whose cube root is the priority, step 2 above) divided by the surface area of the scene box. Small when
/// triangles are small against the grid planes that cross them (scanned and tessellated models: the shared bunny and
/// dragon 0.03-0.05), large when big or long thin triangles waste box area at coarse planes (Crytek Sponza 4.7, the
/// conference room 2.6, the slivers stress scene 374). Estimated from every k-th triangle id, k = ceil(n /
/// max_samples) (0: every triangle), the sum scaled by k: a few large triangles can dominate the sum, so the default
/// keeps many samples (Sponza's estimate is 5.5 with 65,536 of its 262,205 triangles, but 1.8 with 8,192). 0 for
/// other primitive kinds, empty scenes and flat scene boxes of zero area. Parallel (TBB), the same value with any
/// number of threads.
double presplit_potential(const Scene& scene, std::uint32_t max_samples = 65536);

/// The build references of `scene` with large triangles pre-split. For scenes of spheres or user primitives, or a
/// fraction <= 0, the result is exactly scene.build_references(). At most floor(fraction * n) references are added
/// for n valid triangles. Parallel (TBB).
PresplitResult presplit_references(const Scene& scene, const PresplitOptions& config);

}  // namespace rayaccel
