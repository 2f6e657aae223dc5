// Spatial-split BVH builder (Stich, Friedrich, Dietrich 2009, "Spatial Splits in Bounding Volume Hierarchies"):
// besides binned object splits, a node may be cut by an axis-aligned plane; triangles crossing it are clipped to the
// node's box and each side keeps the bounds of its part, so a primitive may be referenced by several leaves.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "rayaccel/bvh/build_tree.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {

struct SbvhOptions {
  std::uint32_t max_leaf_size = 4;  ///< largest leaf; smaller leaves are made when the SAH prefers them
  SahCosts costs;                   ///< traversal 1, intersection 1
  std::uint32_t bin_count = 16;     ///< bins per axis for object and spatial splits, 2..64
  float max_growth = 1.3f;          ///< memory bound: references never exceed this multiple of the primitive count
  float overlap_alpha = 1e-5f;      ///< spatial splits are tried when the best object split's children overlap by
                                    ///< more than this fraction of the root's area (the paper's alpha)
  /// References a leaf tests at once (a power of two, 1..64): the SAH charges `costs.intersection` per started block
  /// of this many, as BinnedSahOptions::block_size does.
  std::uint32_t block_size = 1;
};

/// Builds over the scene's references. Triangles are clipped; for spheres and user primitives only object splits
/// are made (the result is then an ordinary binned SAH tree without reference duplication).
BuildTree build_sbvh(const Scene& scene, const SbvhOptions& config);

}  // namespace rayaccel
