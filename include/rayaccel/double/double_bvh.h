// The BVH in double: a Bvh<AabbVolume> over float boxes rounded outward from the double triangles about an anchor,
// walked with the conservative double slab test (Ize 2013) and the double watertight kernel (Woop et al. 2013).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "rayaccel/bv/aabb_volume.h"
#include "rayaccel/bvh/binary_traversal.h"
#include "rayaccel/bvh/bvh.h"
#include "rayaccel/double/double_accelerator.h"
#include "rayaccel/geometry/ray_box_d.h"
#include "rayaccel/geometry/ray_triangle_d.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {

/// Far bound for culling boxes: hit.t widened by 2^-32 relative, so a triangle whose t ties the current hit within
/// the kernel's rounding is still tested and the answer matches brute force (as bvh_cull_bound does for float).
inline double double_bvh_cull_bound(double t) { return t + std::fabs(t) * 0x1p-32; }

class DoubleBvh final : public DoubleAcceleratorImpl<DoubleBvh> {
 public:
  /// Checks the options (throws Error naming a bad value).
  explicit DoubleBvh(BvhOptions options = {}) : tree_(options) {}

  void build(const DoubleScene& scene) override;
  std::size_t memory_bytes() const override;
  /// The tree's own invariants, and every leaf triangle inside its leaf's box (compared exactly in double).
  std::vector<std::string> validate() const override;
  /// The float tree the traversal walks.
  const Bvh<AabbVolume>& tree() const { return tree_; }

  template <bool AnyHit>
  void trace(const PreparedRayD& ray, HitD& hit) const;

 private:
  Bvh<AabbVolume> tree_;
  DVec3 anchor_;                                 ///< the boxes' origin
  Scene boxes_;                                  ///< the float boxes (relative to anchor_) as user primitives
  std::vector<std::array<DVec3, 3>> triangles_;  ///< per leaf slot: the double triangle, in leaf order
  std::vector<std::uint32_t> prim_ids_;          ///< per leaf slot: the scene's triangle id
};

template <bool AnyHit>
void DoubleBvh::trace(const PreparedRayD& ray, HitD& hit) const {
  const auto& nodes = tree_.nodes();
  if (nodes.empty()) return;
  const BoxFrameD frame(ray, anchor_);
  using Node = Bvh<AabbVolume>::Node;
  NoStats stats;
  traverse_binary_bvh<AnyHit>(
      nodes.data(), 0, ray.t_min,
      [&](const Node& node, double t_far, double* t_entry) {
        return intersect_box(ray, frame, node.volume.box, ray.t_min, t_far, t_entry);
      },
      [&](const Node& node) {
        for (std::uint32_t slot = node.index, end = node.index + node.count; slot < end; ++slot) {
          const auto& v = triangles_[slot];
          if (intersect_triangle(ray, v[0], v[1], v[2], prim_ids_[slot], hit) && AnyHit) return true;
        }
        return false;
      },
      [&] { return double_bvh_cull_bound(hit.t); }, stats);
}

}  // namespace rayaccel
