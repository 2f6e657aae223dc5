// Brute force: the oracle. Tests every valid primitive in id order.
#include "rayaccel/accel/brute_force.h"

namespace rayaccel {

void BruteForce::build(const Scene& scene) {
  scene_ = &scene;
  prim_ids_.clear();
  prim_ids_.reserve(scene.primitive_count());
  for (std::uint32_t id = 0; id < scene.primitive_count(); ++id) {
    if (scene.is_valid(id)) prim_ids_.push_back(id);
  }
}

std::vector<std::string> BruteForce::validate() const {
  std::vector<std::string> problems;
  if (!scene_) return {"not built"};
  std::uint32_t valid = 0;
  for (std::uint32_t id = 0; id < scene_->primitive_count(); ++id) valid += scene_->is_valid(id) ? 1 : 0;
  if (valid != prim_ids_.size()) problems.push_back("primitive list does not hold every valid primitive once");
  for (std::size_t i = 1; i < prim_ids_.size(); ++i) {
    if (prim_ids_[i] <= prim_ids_[i - 1]) problems.push_back("primitive list is not in strictly increasing id order");
  }
  return problems;
}

void register_brute_force(std::vector<AcceleratorInfo>& registry) {
  registry.push_back({"brute_force", "tests every primitive; the oracle every other structure must agree with", {}, {},
                      [](const OptionValues&) { return std::make_unique<BruteForce>(); }, false, {}});
}

}  // namespace rayaccel
