// DoubleBvh: the float tree built over the outward-rounded boxes of the double triangles, then the double triangles
// copied into leaf order.
#include "rayaccel/double/double_bvh.h"

#include <string>

namespace rayaccel {

void DoubleBvh::build(const DoubleScene& scene) {
  UserPrimitives prims;
  prims.count = scene.triangle_count();
  const DoubleScene* s = &scene;
  const AABB& bounds = scene.bounds();
  anchor_ = bounds.is_empty() ? DVec3{} : (DVec3(bounds.lo) + DVec3(bounds.hi)) * 0.5;
  const DVec3 anchor = anchor_;
  prims.bounds = [s, anchor](std::uint32_t id) { return anchored_float_box(s->triangle(id), anchor); };
  // The float tree only needs boxes; its own traversal is never run over them.
  prims.intersect = [](std::uint32_t, const PreparedRay&, Hit&) { return false; };
  boxes_ = Scene::from_user(std::move(prims), "double boxes");
  tree_.build(boxes_);
  triangles_.clear();
  prim_ids_.clear();
  std::uint32_t slots = 0;
  for (const auto& node : tree_.nodes()) {
    if (node.is_leaf()) slots = std::max(slots, node.index + node.count);
  }
  triangles_.resize(slots);
  prim_ids_.resize(slots);
  for (std::uint32_t slot = 0; slot < slots; ++slot) {
    prim_ids_[slot] = tree_.slot_prim_id(slot);
    triangles_[slot] = scene.triangle(prim_ids_[slot]);
  }
}

std::size_t DoubleBvh::memory_bytes() const {
  return tree_.memory_bytes() + triangles_.size() * sizeof(triangles_[0]) + prim_ids_.size() * sizeof(std::uint32_t);
}

std::vector<std::string> DoubleBvh::validate() const {
  std::vector<std::string> problems = tree_.validate();
  const auto& nodes = tree_.nodes();
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    if (!nodes[n].is_leaf()) continue;
    const AABB& box = nodes[n].volume.box;
    for (std::uint32_t slot = nodes[n].index; slot < nodes[n].index + nodes[n].count; ++slot) {
      if (!box.contains(anchored_float_box(triangles_[slot], anchor_))) {
        problems.push_back("double bvh: triangle " + std::to_string(prim_ids_[slot]) + " leaves the box of node " +
                           std::to_string(n));
      }
    }
  }
  return problems;
}

}  // namespace rayaccel
