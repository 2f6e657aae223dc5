// Brute force: tests every primitive. The oracle every other structure is checked against.
#pragma once

#include <cstdint>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/registry.h"

namespace rayaccel {

class BruteForce final : public AcceleratorImpl<BruteForce> {
 public:
  void build(const Scene& scene) override;
  std::size_t memory_bytes() const override { return prim_ids_.size() * sizeof(std::uint32_t); }
  std::vector<std::string> validate() const override;

  template <bool AnyHit, class Stats>
  void trace(const PreparedRay& ray, Hit& hit, Stats& stats) const {
    stats.visit_node();
    for (std::uint32_t id : prim_ids_) {
      stats.test_primitive();
      if (scene_->intersect(id, ray, hit) && AnyHit) return;
    }
  }

 private:
  const Scene* scene_ = nullptr;
  std::vector<std::uint32_t> prim_ids_;  ///< valid primitives in id order (lowest id wins a tie in t)
};

void register_brute_force(std::vector<AcceleratorInfo>& registry);

}  // namespace rayaccel
