// The BVH in double: a Bvh<AabbVolume> over float boxes rounded outward from the double triangles relative to
// an anchor, walked with the conservative double slab test (Ize 2013) and the double watertight kernel (Woop et al.
// 2013).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "rayaccel/bv/aabb_volume.h"
#include "rayaccel/bvh/bvh.h"
#include "rayaccel/double/double_accelerator.h"
#include "rayaccel/geometry/ray_box_d.h"
#include "rayaccel/geometry/ray_triangle_d.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {

// The BVH in double: the tree is Bvh<AabbVolume> (any of its builders: binned SAH after Wald 2007, sweep, lbvh,
// ploc, sbvh with object splits only) built over float boxes rounded outward from the double triangles taken relative
// to an anchor (the centre of the scene's bounds), so every box contains its triangles exactly and keeps float's
// resolution near the scene (not float's ulp at 1e7, which is 1); traversal tests a double ray against those boxes
// conservatively (Ize 2013, geometry/ray_box_d.h) and leaves with the double watertight kernel (Woop, Benthin, Wald
// 2013, geometry/ray_triangle_d.h).

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
  double t_entry = ray.t_min;
  if (!intersect_box(ray, frame, nodes[0].volume.box, ray.t_min, double_bvh_cull_bound(hit.t), &t_entry)) return;
  struct Entry {
    std::uint32_t node;
    double t_entry;
  };
  Entry stack[kBvhMaxDepth];  // one deferred sibling per level at most (the tree's depth bound)
  int top = 0;
  std::uint32_t current = 0;
  for (;;) {
    const auto& node = nodes[current];
    if (node.count > 0) {
      for (std::uint32_t slot = node.index, end = node.index + node.count; slot < end; ++slot) {
        const auto& v = triangles_[slot];
        if (intersect_triangle(ray, v[0], v[1], v[2], prim_ids_[slot], hit) && AnyHit) return;
      }
    } else {
      const std::uint32_t first = current + 1, second = node.index;
      double t_first = ray.t_min, t_second = ray.t_min;
      const double t_far = double_bvh_cull_bound(hit.t);
      const bool hit_first = intersect_box(ray, frame, nodes[first].volume.box, ray.t_min, t_far, &t_first);
      const bool hit_second = intersect_box(ray, frame, nodes[second].volume.box, ray.t_min, t_far, &t_second);
      if (hit_first && hit_second) {
        if (!AnyHit && t_second < t_first) {
          stack[top++] = {first, t_first};
          current = second;
        } else {
          stack[top++] = {second, t_second};
          current = first;
        }
        continue;
      }
      if (hit_first || hit_second) {
        current = hit_first ? first : second;
        continue;
      }
    }
    for (;;) {
      if (top == 0) return;
      const Entry e = stack[--top];
      if (e.t_entry <= double_bvh_cull_bound(hit.t)) {
        current = e.node;
        break;
      }
    }
  }
}

}  // namespace rayaccel
