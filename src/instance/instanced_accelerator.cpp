// InstancedAccelerator: bottom levels from the registry, the top level over world boxes, and the two-level
// traversal (top-level BVH, then each reached instance's bottom level on the ray mapped to its object space).
#include "rayaccel/instance/instanced_accelerator.h"

#include <utility>

#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/core/float_rounding.h"

namespace rayaccel {

InstancedAccelerator::InstancedAccelerator(InstancedAcceleratorOptions options) : options_(std::move(options)) {
  make_accelerator(options_.bottom);  // an unknown spec fails here, naming the known structures or keys
  if (options_.top != kTopLevelBvh) user_top_ = make_accelerator(options_.top);
}

Hit InstancedAccelerator::trace_instance(std::uint32_t index, const Ray& ray) const {
  const Placed& p = placed_[index];
  return bottoms_[p.geometry]->intersect(object_ray(p, ray));
}

UserPrimitives InstancedAccelerator::top_primitives() const {
  UserPrimitives prims;
  prims.count = static_cast<std::uint32_t>(placed_.size());
  prims.bounds = [this](std::uint32_t index) { return boxes_[index]; };
  prims.intersect = [this](std::uint32_t index, const PreparedRay& prepared, Hit& hit) {
    if (!enabled_[index]) return false;
    // hit.t is the exclusive far bound (Hit::begin()); the bottom level takes an inclusive one. The direction is the
    // one every kernel reads (readable_direction()), so an identity instance still sees the world ray.
    const float t_max = hit.t == std::numeric_limits<float>::infinity() ? hit.t : next_float_down(hit.t);
    const Hit found = trace_instance(index, Ray{prepared.origin, prepared.t_min, prepared.direction, t_max});
    if (!found.found() || !(found.t < hit.t)) return false;
    hit = Hit{found.t, index, found.u, found.v};
    return true;
  };
  return prims;
}

UpdateKind InstancedAccelerator::build_user_top(bool refit) {
  try {
    if (!top_scene_) top_scene_ = std::make_unique<Scene>();
    *top_scene_ = Scene::from_user(top_primitives(), "instances");  // same address: update() may refit
    if (refit) return user_top_->update(*top_scene_);
    user_top_->build(*top_scene_);
    return UpdateKind::rebuilt;
  } catch (const Error& e) {
    throw Error("InstancedAccelerator: top level '" + options_.top + "' cannot be built over the instances (user " +
                "primitives): " + e.what());
  }
}

void InstancedAccelerator::build(const InstancedScene& scene) {
  scene_ = &scene;
  enabled_.clear();
  bottoms_.clear();
  for (std::uint32_t g = 0; g < scene.geometry_count(); ++g) {
    bottoms_.push_back(make_accelerator(options_.bottom));
    bottoms_.back()->build(scene.geometry(g));
  }
  rebuild_top();
}

void InstancedAccelerator::place_instances() {
  if (!scene_) throw Error("InstancedAccelerator: build() has not been called");
  const InstancedScene& scene = *scene_;
  if (bottoms_.size() != scene.geometry_count()) {
    throw Error("InstancedAccelerator: the scene has " + std::to_string(scene.geometry_count()) +
                " geometries, the structure was built over " + std::to_string(bottoms_.size()) + " (call build())");
  }
  placed_.resize(scene.instance_count());
  boxes_.resize(scene.instance_count());
  enabled_.resize(scene.instance_count(), 1);
  for (std::uint32_t i = 0; i < scene.instance_count(); ++i) {
    const Instance& instance = scene.instance(i);
    placed_[i] = Placed{instance.inverse, instance.geometry, instance.instance_id, instance.transform.is_identity()};
    boxes_[i] = transform_box(instance.transform, scene.geometry(instance.geometry).bounds());
  }
}

void InstancedAccelerator::rebuild_top() {
  place_instances();
  if (user_top()) {
    build_user_top(false);
  } else {
    top_.build(boxes_);
  }
}

UpdateKind InstancedAccelerator::update_top() {
  const std::size_t before = placed_.size();
  place_instances();
  if (user_top()) return build_user_top(placed_.size() == before);
  if (placed_.size() != before) {
    top_.build(boxes_);
    return UpdateKind::rebuilt;
  }
  top_.refit(boxes_);
  return UpdateKind::refitted;
}

void InstancedAccelerator::set_enabled(std::uint32_t instance, bool enabled) {
  if (instance >= enabled_.size()) {
    throw Error("set_enabled: instance " + std::to_string(instance) + " is out of range (the structure holds " +
                std::to_string(enabled_.size()) + " instances)");
  }
  enabled_[instance] = enabled ? 1 : 0;
}

bool InstancedAccelerator::is_enabled(std::uint32_t instance) const {
  if (instance >= enabled_.size()) {
    throw Error("is_enabled: instance " + std::to_string(instance) + " is out of range (the structure holds " +
                std::to_string(enabled_.size()) + " instances)");
  }
  return enabled_[instance] != 0;
}

InstanceHit InstancedAccelerator::intersect(const Ray& ray) const {
  InstanceHit best;
  const PreparedRay prepared(ray);
  if (prepared.is_void()) return best;
  if (user_top()) {
    // The ray as the top level's callbacks see it (the direction as kernels read it), so that tracing the
    // instance it names again, up to its t (inclusive), maps the same ray and finds that t; that recovers the
    // bottom level's primitive, u and v (at a tie, possibly another primitive at exactly that t).
    Ray again{prepared.origin, prepared.t_min, prepared.direction, prepared.t_max};
    const Hit top_hit = user_top_->intersect(again);
    if (!top_hit.found()) return best;
    again.t_max = top_hit.t;
    const Hit hit = trace_instance(top_hit.prim_id, again);
    const Placed& p = placed_[top_hit.prim_id];
    if (!hit.found()) {
      throw Error("InstancedAccelerator: instance " + std::to_string(top_hit.prim_id) + " traced again missed");
    }
    return InstanceHit{hit.t, hit.prim_id, hit.u, hit.v, p.instance_id, top_hit.prim_id, p.geometry};
  }
  float t_far = ray.t_max;
  top_.traverse(prepared, t_far, [&](std::uint32_t index, float& far) {
    if (!enabled_[index]) return false;
    const Placed& p = placed_[index];
    Ray local = object_ray(p, ray);
    local.t_max = far;
    const Hit hit = bottoms_[p.geometry]->intersect(local);
    if (hit.found() && (!best.found() || hit.t < best.t)) {
      best = InstanceHit{hit.t, hit.prim_id, hit.u, hit.v, p.instance_id, index, p.geometry};
      far = hit.t;
    }
    return false;
  });
  return best;
}

bool InstancedAccelerator::occluded(const Ray& ray) const {
  const PreparedRay prepared(ray);
  if (prepared.is_void()) return false;
  if (user_top()) return user_top_->occluded(ray);
  bool found = false;
  float t_far = ray.t_max;
  top_.traverse(prepared, t_far, [&](std::uint32_t index, float&) {
    if (!enabled_[index]) return false;
    const Placed& p = placed_[index];
    found = bottoms_[p.geometry]->occluded(object_ray(p, ray));
    return found;
  });
  return found;
}

void InstancedAccelerator::intersect(std::span<const Ray> rays, std::span<InstanceHit> hits) const {
  detail::check_batch_sizes(rays.size(), hits.size(), 0);
  detail::parallel_for_rays(rays.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) hits[i] = intersect(rays[i]);
  });
}

void InstancedAccelerator::occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded_out) const {
  detail::check_batch_sizes(rays.size(), occluded_out.size(), 0);
  detail::parallel_for_rays(rays.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) occluded_out[i] = occluded(rays[i]) ? 1 : 0;
  });
}

std::size_t InstancedAccelerator::bottom_memory_bytes() const {
  std::size_t bytes = 0;
  for (const auto& bottom : bottoms_) bytes += bottom->memory_bytes();
  return bytes;
}

std::size_t InstancedAccelerator::top_memory_bytes() const {
  std::size_t top_bytes = top_.memory_bytes();
  if (user_top()) top_bytes = user_top_->memory_bytes() + (top_scene_ ? top_scene_->memory_bytes() : 0);
  return top_bytes + placed_.capacity() * sizeof(Placed) + boxes_.capacity() * sizeof(AABB) +
         enabled_.capacity();
}

std::vector<std::string> InstancedAccelerator::validate() const {
  std::vector<std::string> problems;
  for (std::size_t g = 0; g < bottoms_.size(); ++g) {
    for (const std::string& line : bottoms_[g]->validate()) {
      problems.push_back("geometry " + std::to_string(g) + ": " + line);
    }
  }
  if (user_top()) {
    for (const std::string& line : user_top_->validate()) problems.push_back("top: " + line);
  } else {
    for (std::string& line : top_.validate(boxes_)) problems.push_back(std::move(line));
  }
  return problems;
}

}  // namespace rayaccel
