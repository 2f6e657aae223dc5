// DoubleAccelerator: the runtime interface of the double-precision path, and DoubleAcceleratorImpl, which derives
// it from one templated traversal as AcceleratorImpl does ("brute_force", or "bvh" with bv=aabb).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rayaccel/core/ray_d.h"
#include "rayaccel/double/double_scene.h"

namespace rayaccel {

class DoubleAccelerator {
 public:
  virtual ~DoubleAccelerator() = default;

  /// The spec this instance was made from, e.g. "bvh:builder=ploc".
  const std::string& spec() const { return spec_; }
  void set_spec(std::string spec) { spec_ = std::move(spec); }

  /// Builds (or rebuilds) over `scene`, which must outlive this object and stay at the same address.
  virtual void build(const DoubleScene& scene) = 0;
  /// Closest hit with ray.t_min < t <= ray.t_max; a miss has prim_id == kInvalidPrimId and t = +inf. Void rays
  /// (core/ray_d.h: NaN, Inf, components outside the double domain, zero direction, t_max < t_min) miss.
  virtual HitD intersect(const RayD& ray) const = 0;
  /// True when anything is hit with ray.t_min < t <= ray.t_max; stops at the first hit found.
  virtual bool occluded(const RayD& ray) const = 0;
  /// Parallel batches; sizes must match (Error otherwise).
  virtual void intersect(std::span<const RayD> rays, std::span<HitD> hits) const = 0;
  virtual void occluded(std::span<const RayD> rays, std::span<std::uint8_t> occluded) const = 0;
  /// Bytes of the structure's own data (the scene's arrays are not counted).
  virtual std::size_t memory_bytes() const = 0;
  /// Checks the structure's invariants; one line per violation (empty when valid).
  virtual std::vector<std::string> validate() const = 0;

 private:
  std::string spec_;
};

namespace detail {
/// Parallel batch drivers shared by every double structure (accel/accelerator.h's chunking and size checks).
void trace_batch_d(std::span<const RayD> rays, std::size_t outputs,
                   const std::function<void(std::size_t, std::size_t)>& body);
}  // namespace detail

/// Implements DoubleAccelerator from one member of Derived:
///   template <bool AnyHit> void trace(const PreparedRayD& ray, HitD& hit) const;
/// `hit` arrives as HitD::begin(ray); with AnyHit trace() may return at the first hit.
template <class Derived>
class DoubleAcceleratorImpl : public DoubleAccelerator {
 public:
  HitD intersect(const RayD& ray) const final { return trace_one<false>(ray); }
  bool occluded(const RayD& ray) const final { return trace_one<true>(ray).found(); }
  void intersect(std::span<const RayD> rays, std::span<HitD> hits) const final {
    detail::trace_batch_d(rays, hits.size(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) hits[i] = trace_one<false>(rays[i]);
    });
  }
  void occluded(std::span<const RayD> rays, std::span<std::uint8_t> occluded) const final {
    detail::trace_batch_d(rays, occluded.size(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) occluded[i] = trace_one<true>(rays[i]).found() ? 1 : 0;
    });
  }

 private:
  template <bool AnyHit>
  HitD trace_one(const RayD& ray) const {
    const PreparedRayD prepared(ray);
    HitD hit = HitD::begin(prepared);
    static_cast<const Derived*>(this)->template trace<AnyHit>(prepared, hit);
    hit.finish();
    return hit;
  }
};

/// Creates an unbuilt double structure from a spec: "brute_force", or "bvh[:key=value,...]" with the float bvh's
/// options (bv=aabb only). Throws Error naming an unknown name, key or value.
std::unique_ptr<DoubleAccelerator> make_double_accelerator(std::string_view spec);
/// The names make_double_accelerator() knows.
std::vector<std::string> double_accelerator_names();

}  // namespace rayaccel
