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

struct SbvhConfig {
  std::uint32_t max_leaf_size = 4;  ///< largest leaf; smaller leaves are made when the SAH prefers them
  SahCosts costs;                   ///< traversal 1, intersection 1
  std::uint32_t bin_count = 16;     ///< bins per axis for object and spatial splits, 2..64
  float max_growth = 1.3f;          ///< memory bound: references never exceed this multiple of the primitive count
  float overlap_alpha = 1e-5f;      ///< spatial splits are tried when the best object split's children overlap by
                                    ///< more than this fraction of the root's area (the paper's alpha)
};

/// Room for a triangle clipped by a box's six planes (9 vertices) plus the one spare clip_polygon_to_axis_plane needs.
using ClippedPolygon = std::array<Vec3, 10>;

/// Clips triangle (a, b, c) to `box` widened by widen_for_clipping() and returns the vertex count of the polygon left
/// in `out` (0 when the triangle misses the box): the points a volume is fitted to for one SBVH reference.
int clip_triangle_polygon(const std::array<Vec3, 3>& triangle, const AABB& box, ClippedPolygon& out);

/// Builds over the scene's references. Triangles are clipped; for spheres and user primitives only object splits
/// are made (the result is then an ordinary binned SAH tree without reference duplication).
BuildTree build_sbvh(const Scene& scene, const SbvhConfig& config);

}  // namespace rayaccel
