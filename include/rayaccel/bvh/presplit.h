// Triangle pre-splitting (Karras & Aila 2013, "Fast Parallel Construction of High-Quality Bounding Volume
// Hierarchies", HPG 2013, section on triangle splitting; the older idea is Ernst & Greiner 2007, "Early Split
// Clipping for Bounding Volume Hierarchies"): before an ordinary object-split build, large or badly fitting triangles
// are cut into several references, each with the box of one piece, so the builder gets part of the quality of
// spatial splits (SBVH) at a small fraction of their cost.
//
// Algorithm:
// 1. A power-of-two grid over the scene box defines a hierarchy of planes: on each axis the plane at 1/2 is level 0,
//    those at 1/4 and 3/4 level 1, and so on; interleaving the axes as a Morton code does (x, y, z) gives every plane
//    a depth d = 3 * level + axis. Planes of small depth are the ones a top-down build is most likely to split at.
// 2. Each triangle gets the priority p = (2^-d * (A_box - A_ideal))^(1/3), where A_box is the surface area of its box,
//    A_ideal = |n_x| + |n_y| + |n_z| for the edge cross product n (twice the sum of the projected areas: the box area
//    that infinitely many pieces would approach) and d the depth of the coarsest plane that crosses the box (p = 0 when
//    none does).
// 3. A budget of floor(fraction * n) extra references is shared in proportion to priority: triangle t is cut into
//    floor(beta * p_t) + 1 pieces, beta the largest value (found by bisection) for which the total stays in budget.
// 4. A triangle's box is split recursively at the coarsest grid plane crossing it; each half's box is the triangle
//    clipped to that half (clip_triangle_to_box, conservative and inside the half), and the pieces still to make are
//    shared between the halves in proportion to their longest extent. A split that leaves one half empty or finds no
//    plane ends that branch early, so a triangle may get fewer pieces than planned, never more.
//
// Every piece box lies inside the triangle's box, and the piece boxes together contain every point of the triangle.
// Pieces keep the triangle's prim_id, so a tree built over them is a tree with spatial splits
// (BuildTree::spatial_splits): a primitive may sit in several leaves.
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
