// InstancedAccelerator: a two-level structure over an InstancedScene: a bottom-level structure per geometry
// (any registry spec) under a top level over the instances' world boxes, as Embree's instancing and pbrt-v4's
// TransformedPrimitive.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/instance/instanced_scene.h"
#include "rayaccel/instance/top_level_bvh.h"

namespace rayaccel {

/// A closest hit in an instanced scene: the bottom level's Hit fields (t, prim_id and u, v of the geometry's
/// primitive) plus which instance and geometry it was found in. A miss has t = +inf and every id kInvalidPrimId.
struct InstanceHit {
  float t = std::numeric_limits<float>::infinity();
  std::uint32_t prim_id = kInvalidPrimId;   ///< primitive of the geometry
  float u = 0.0f;
  float v = 0.0f;
  std::uint32_t instance_id = kInvalidPrimId;  ///< the Instance::instance_id of the instance hit
  std::uint32_t instance = kInvalidPrimId;     ///< its index in the scene
  std::uint32_t geom_id = kInvalidPrimId;      ///< its geometry index

  bool found() const { return prim_id != kInvalidPrimId; }
  /// The Hit fields alone.
  Hit hit() const { return Hit{t, prim_id, u, v}; }
};

struct InstancedAcceleratorOptions {
  /// Registry spec of every bottom-level structure, e.g. "bvh_wide", "bvh:bv=obb", "kdtree" (any registered name).
  std::string bottom = "bvh_wide";
  /// The top level: kTopLevelBvh (TopLevelBvh) or a registry spec built over one user primitive per instance.
  std::string top = "bvh_top";
};

/// The `top` value that selects TopLevelBvh.
inline constexpr const char* kTopLevelBvh = "bvh_top";

class InstancedAccelerator {
 public:
  explicit InstancedAccelerator(InstancedAcceleratorOptions options = {});
  // A user-primitive top level's callbacks refer to this object: it stays where it was made.
  InstancedAccelerator(const InstancedAccelerator&) = delete;
  InstancedAccelerator& operator=(const InstancedAccelerator&) = delete;

  /// Builds one bottom level per geometry and the top level. `scene` must outlive this object and stay at the same
  /// address. Throws Error for an unknown bottom spec (from the registry), or a top structure that cannot be built
  /// over user primitives.
  void build(const InstancedScene& scene);
  /// Rebuilds only the top level, from the scene's current transforms (after InstancedScene::set_transform()); the
  /// bottom levels stay. Queries see the transforms of the last build() or rebuild_top().
  void rebuild_top();
  /// Like rebuild_top(), but keeps the top level's tree and recomputes its boxes bottom-up from the instances' new
  /// world boxes (refitted), unless the scene's instance count changed since, when it rebuilds (rebuilt).
  UpdateKind update_top();

  /// Shows or hides instance `instance` (an index into the scene) from every later query, without a rebuild; all
  /// are enabled after build(), and rebuild_top() / update_top() keep the setting (instances added since start
  /// enabled). Throws Error for an index out of range.
  void set_enabled(std::uint32_t instance, bool enabled);
  bool is_enabled(std::uint32_t instance) const;

  /// Closest hit with ray.t_min < t <= ray.t_max over all instances; a miss has found() false and t = +inf. A void
  /// ray (see PreparedRay) misses. Of hits at the same t in two instances, the first found is kept.
  InstanceHit intersect(const Ray& ray) const;
  /// True when any instance is hit with ray.t_min < t <= ray.t_max.
  bool occluded(const Ray& ray) const;
  /// Parallel batches (TBB); sizes must match (Error otherwise).
  void intersect(std::span<const Ray> rays, std::span<InstanceHit> hits) const;
  void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded) const;

  const std::string& bottom_spec() const { return options_.bottom; }
  const Accelerator& bottom(std::uint32_t geometry) const { return *bottoms_[geometry]; }
  const std::string& top_spec() const { return options_.top; }
  /// The TopLevelBvh (empty when `top` names a registry structure).
  const TopLevelBvh& top() const { return top_; }
  /// Bytes of the bottom levels' own data (each geometry once).
  std::size_t bottom_memory_bytes() const;
  /// Bytes of the top level: its nodes plus the per-instance records (inverse transform, geometry, id) it traces with.
  std::size_t top_memory_bytes() const;
  std::size_t memory_bytes() const { return bottom_memory_bytes() + top_memory_bytes(); }
  /// The bottom levels' validate() (each line prefixed with its geometry) and the top level's; empty when valid.
  std::vector<std::string> validate() const;

 private:
  struct Placed {
    Affine3 world_to_object;
    std::uint32_t geometry = 0;
    std::uint32_t instance_id = 0;
    bool identity = false;  ///< the transform is exactly the identity: trace the world ray itself
  };

  /// Fills placed_ and boxes_ from the scene's current instances; keeps enabled_ (new instances enabled).
  void place_instances();
  /// The ray as instance `p` sees it.
  static Ray object_ray(const Placed& p, const Ray& ray) {
    return p.identity ? ray : transform_ray(p.world_to_object, ray);
  }
  bool user_top() const { return user_top_ != nullptr; }
  /// Builds (or, with `refit`, updates) the registry top level over the current placed_ and boxes_.
  UpdateKind build_user_top(bool refit);
  /// The user primitives of the registry top level: one per instance.
  UserPrimitives top_primitives() const;
  /// Closest hit of instance `index` with t_min < t <= t_max (the ray in world space), in its bottom level.
  Hit trace_instance(std::uint32_t index, const Ray& ray) const;

  InstancedAcceleratorOptions options_;
  const InstancedScene* scene_ = nullptr;
  std::vector<std::unique_ptr<Accelerator>> bottoms_;
  std::vector<Placed> placed_;
  std::vector<AABB> boxes_;
  std::vector<std::uint8_t> enabled_;  ///< per instance: 1 when queries see it
  TopLevelBvh top_;
  std::unique_ptr<Accelerator> user_top_;  ///< the registry top level, when options_.top is not kTopLevelBvh
  std::unique_ptr<Scene> top_scene_;       ///< its user primitives (kept at one address so that it can refit)
};

}  // namespace rayaccel
