// Brute force in double: every triangle tested with the double watertight kernel (Woop, Benthin, Wald 2013;
// geometry/ray_triangle_d.h). The oracle the double BVH is checked against.
#pragma once

#include "rayaccel/double/double_accelerator.h"
#include "rayaccel/geometry/ray_triangle_d.h"

namespace rayaccel {

class DoubleBruteForce final : public DoubleAcceleratorImpl<DoubleBruteForce> {
 public:
  void build(const DoubleScene& scene) override { scene_ = &scene; }
  template <bool AnyHit>
  void trace(const PreparedRayD& ray, HitD& hit) const {
    if (scene_ == nullptr) return;
    for (std::uint32_t id = 0, n = scene_->triangle_count(); id < n; ++id) {
      const auto& t = scene_->triangle(id);
      if (intersect_triangle(ray, t[0], t[1], t[2], id, hit) && AnyHit) return;
    }
  }
  std::size_t memory_bytes() const override { return 0; }
  std::vector<std::string> validate() const override { return {}; }

 private:
  const DoubleScene* scene_ = nullptr;
};

}  // namespace rayaccel
