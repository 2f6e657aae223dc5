// Brute force: tests every primitive. The oracle every other structure is checked against.
#pragma once

#include <array>
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
      if (test_scene_primitive(*scene_, id, ray, hit, stats) && AnyHit) return;
    }
  }

  /// The queries beyond the first hit (see detail::StructureWithQueries): every valid triangle is a candidate.
  void find_crossings(HitList& list) const { for_each_triangle("all-hits", list); }
  void find_closest_point(ClosestPointSearch& search) const { for_each_triangle("closest-point", search); }

 private:
  template <class Query>
  void for_each_triangle(const char* name, Query& query) const {
    if (!scene_) return;
    detail::require_triangle_scene(*scene_, name);
    for (std::uint32_t id : prim_ids_) {
      const std::array<Vec3, 3> t = scene_->triangle(id);
      query.test(id, t[0], t[1], t[2]);
    }
  }

  const Scene* scene_ = nullptr;
  std::vector<std::uint32_t> prim_ids_;  ///< valid primitives in id order (lowest id wins a tie in t)
};

void register_brute_force(std::vector<AcceleratorInfo>& registry);

}  // namespace rayaccel
