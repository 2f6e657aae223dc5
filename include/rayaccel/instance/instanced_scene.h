// InstancedScene: the input of a two-level structure — bottom-level geometries (each a Scene) and instances that
// place one of them in the world by an affine transform (object to world) and name it by an instance id, as in
// Embree's instanced scenes (rtcNewGeometry(RTC_GEOMETRY_TYPE_INSTANCE)) and pbrt-v4's object instances.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "rayaccel/instance/affine.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {

struct Instance {
  std::uint32_t geometry = 0;     ///< index into InstancedScene::geometries()
  Affine3 transform;              ///< object to world
  Affine3 inverse;                ///< world to object (computed when the transform is set)
  std::uint32_t instance_id = 0;  ///< the caller's name for the instance, reported in every hit
};

class InstancedScene {
 public:
  /// Adds a bottom-level geometry (moved in, or shared with the caller); returns its index. Any primitive kind.
  /// Throws Error for a null pointer.
  std::uint32_t add_geometry(Scene scene);
  std::uint32_t add_geometry(std::shared_ptr<const Scene> scene);

  /// Adds an instance of geometry `geometry` placed by `object_to_world`; returns its index. `instance_id` defaults
  /// to the index. Throws Error (naming the instance) for a geometry index out of range or a transform that is not
  /// finite and invertible (see Affine3::inverse()).
  std::uint32_t add_instance(std::uint32_t geometry, const Affine3& object_to_world);
  std::uint32_t add_instance(std::uint32_t geometry, const Affine3& object_to_world, std::uint32_t instance_id);

  /// Moves instance `index` (the same checks as add_instance). Structures built over the scene see the change after
  /// InstancedAccelerator::rebuild_top() or update_top().
  void set_transform(std::uint32_t index, const Affine3& object_to_world);

  std::uint32_t geometry_count() const { return static_cast<std::uint32_t>(geometries_.size()); }
  std::uint32_t instance_count() const { return static_cast<std::uint32_t>(instances_.size()); }
  const Scene& geometry(std::uint32_t index) const { return *geometries_[index]; }
  const Instance& instance(std::uint32_t index) const { return instances_[index]; }
  const std::vector<Instance>& instances() const { return instances_; }

  /// Primitives over all instances (what flattening would make).
  std::uint64_t flattened_primitive_count() const;
  /// Bytes of the geometries' own arrays (each counted once) and of the instance records.
  std::size_t memory_bytes() const;

 private:
  Instance checked_instance(std::uint32_t index, std::uint32_t geometry, const Affine3& object_to_world,
                            std::uint32_t instance_id) const;

  std::vector<std::shared_ptr<const Scene>> geometries_;
  std::vector<Instance> instances_;
};

}  // namespace rayaccel
