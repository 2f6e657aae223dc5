// InstancedScene: geometries and instances, with the checks on geometry indices and transforms.
#include "rayaccel/instance/instanced_scene.h"

#include <string>
#include <utility>

#include "rayaccel/core/error.h"

namespace rayaccel {

std::uint32_t InstancedScene::add_geometry(Scene scene) {
  return add_geometry(std::make_shared<const Scene>(std::move(scene)));
}

std::uint32_t InstancedScene::add_geometry(std::shared_ptr<const Scene> scene) {
  if (!scene) throw Error("InstancedScene::add_geometry: null scene");
  geometries_.push_back(std::move(scene));
  return geometry_count() - 1;
}

Instance InstancedScene::checked_instance(std::uint32_t index, std::uint32_t geometry, const Affine3& object_to_world,
                                          std::uint32_t instance_id) const {
  const std::string name = "instance " + std::to_string(index);
  if (geometry >= geometry_count()) {
    throw Error(name + ": geometry index " + std::to_string(geometry) + " is out of range (the scene has " +
                std::to_string(geometry_count()) + " geometries)");
  }
  Instance out;
  out.geometry = geometry;
  out.transform = object_to_world;
  out.instance_id = instance_id;
  try {
    out.inverse = object_to_world.inverse();
  } catch (const Error& e) {
    throw Error(name + ": " + e.what());
  }
  return out;
}

std::uint32_t InstancedScene::add_instance(std::uint32_t geometry, const Affine3& object_to_world) {
  return add_instance(geometry, object_to_world, instance_count());
}

std::uint32_t InstancedScene::add_instance(std::uint32_t geometry, const Affine3& object_to_world,
                                           std::uint32_t instance_id) {
  instances_.push_back(checked_instance(instance_count(), geometry, object_to_world, instance_id));
  return instance_count() - 1;
}

void InstancedScene::set_transform(std::uint32_t index, const Affine3& object_to_world) {
  if (index >= instance_count()) {
    throw Error("set_transform: instance " + std::to_string(index) + " is out of range (the scene has " +
                std::to_string(instance_count()) + " instances)");
  }
  const Instance& old = instances_[index];
  instances_[index] = checked_instance(index, old.geometry, object_to_world, old.instance_id);
}

std::uint64_t InstancedScene::flattened_primitive_count() const {
  std::uint64_t count = 0;
  for (const Instance& instance : instances_) count += geometries_[instance.geometry]->primitive_count();
  return count;
}

std::size_t InstancedScene::memory_bytes() const {
  std::size_t bytes = instances_.size() * sizeof(Instance);
  for (const auto& geometry : geometries_) bytes += geometry->memory_bytes();
  return bytes;
}

}  // namespace rayaccel
