// Accelerator: the one runtime interface over every structure (closest hit, any hit, parallel batches, memory,
// statistics, validation), and AcceleratorImpl, which derives all of it from a structure's single templated
// traversal so there is one indirect call per ray or per batch and none per node.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/scene/scene.h"
#include "rayaccel/core/stats.h"

namespace rayaccel {

/// A named figure a structure reports about its build (SAH cost, references per primitive, depth, ...).
struct BuildStatistic {
  std::string name;
  double value = 0.0;
};

class Accelerator {
 public:
  virtual ~Accelerator() = default;

  /// The registry spec this instance was made from, e.g. "bvh:bv=obb,builder=ploc".
  const std::string& spec() const { return spec_; }
  void set_spec(std::string spec) { spec_ = std::move(spec); }

  /// Builds (or rebuilds) over `scene`, which must outlive this object and stay at the same address.
  virtual void build(const Scene& scene) = 0;

  /// Closest hit with ray.t_min < t <= ray.t_max; a miss has prim_id == kInvalidPrimId and t = +inf.
  virtual Hit intersect(const Ray& ray) const = 0;
  virtual Hit intersect(const Ray& ray, TraversalStats& stats) const = 0;
  /// True when anything is hit with ray.t_min < t <= ray.t_max; stops at the first hit found.
  virtual bool occluded(const Ray& ray) const = 0;
  virtual bool occluded(const Ray& ray, TraversalStats& stats) const = 0;

  /// Parallel batches. `stats`, when not empty, receives one record per ray (for heat maps); it must then have
  /// rays.size() entries.
  virtual void intersect(std::span<const Ray> rays, std::span<Hit> hits, std::span<TraversalStats> stats = {}) const = 0;
  virtual void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                        std::span<TraversalStats> stats = {}) const = 0;

  /// Closest hits of a batch of coherent rays (camera rays of neighbouring pixels, say), with the contract of
  /// intersect(rays, hits): structures with a packet traversal (bvh_wide's eight-wide nodes) trace each run of eight
  /// consecutive rays, rays[8k .. 8k + 8), together, sharing node fetches and testing one child box against all
  /// eight rays at once; the others trace the rays one by one. Any rays may share a packet (incoherent ones only cost
  /// speed), and every answer is a closest hit, as from intersect() (a tie in t may name another primitive).
  virtual void intersect_packets(std::span<const Ray> rays, std::span<Hit> hits) const { intersect(rays, hits); }

  /// Bytes of the structure's own data (the scene's arrays are not counted).
  virtual std::size_t memory_bytes() const = 0;
  /// Bytes of input that queries read besides memory_bytes(), for `scene` (the one built over): the Scene's
  /// arrays for rayaccel's structures; for a wrapped library, the geometry buffers it was handed. The sum of the
  /// two is what answering queries holds, and compares libraries on the same terms.
  virtual std::size_t input_memory_bytes(const Scene& scene) const { return scene.memory_bytes(); }
  /// Figures about the last build; may be empty.
  virtual std::vector<BuildStatistic> build_statistics() const { return {}; }
  /// Checks the structure's invariants; returns one line per violation (empty when valid).
  virtual std::vector<std::string> validate() const = 0;

 private:
  std::string spec_;
};

/// Implements the Accelerator interface from one member of Derived:
///   template <bool AnyHit, class Stats> void trace(const PreparedRay& ray, Hit& hit, Stats& stats) const;
/// `hit` arrives as Hit::begin(ray); trace() shrinks hit.t with each closer hit, and with AnyHit may return at
/// the first hit. Stats is TraversalStats or NoStats.
template <class Derived>
class AcceleratorImpl : public Accelerator {
 public:
  Hit intersect(const Ray& ray) const final {
    NoStats stats;
    return trace_one<false>(ray, stats);
  }
  Hit intersect(const Ray& ray, TraversalStats& stats) const final { return trace_one<false>(ray, stats); }
  bool occluded(const Ray& ray) const final {
    NoStats stats;
    return trace_one<true>(ray, stats).found();
  }
  bool occluded(const Ray& ray, TraversalStats& stats) const final { return trace_one<true>(ray, stats).found(); }

  void intersect(std::span<const Ray> rays, std::span<Hit> hits, std::span<TraversalStats> stats = {}) const final;
  void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                std::span<TraversalStats> stats = {}) const final;

 private:
  template <bool AnyHit, class Stats>
  Hit trace_one(const Ray& ray, Stats& stats) const {
    const PreparedRay prepared(ray);
    Hit hit = Hit::begin(prepared);
    if (!prepared.is_void()) static_cast<const Derived*>(this)->template trace<AnyHit>(prepared, hit, stats);
    hit.finish();
    return hit;
  }
};

namespace detail {
/// Runs body(begin, end) over [0, count) in parallel chunks (TBB), every chunk in the calling thread's floating-point
/// environment (see accelerator.cpp); the one place batches are split.
void parallel_for_rays(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body);
/// Rays per packet of intersect_packets().
inline constexpr std::size_t kPacketSize = 8;
/// parallel_for_rays() for intersect_packets(): body(begin, end) gets ray ranges that start at a multiple of
/// kPacketSize and end at one or at `count`, so no packet is split between chunks.
void parallel_for_packets(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body);
void check_batch_sizes(std::size_t rays, std::size_t outputs, std::size_t stats);
}  // namespace detail

template <class Derived>
void AcceleratorImpl<Derived>::intersect(std::span<const Ray> rays, std::span<Hit> hits,
                                         std::span<TraversalStats> stats) const {
  detail::check_batch_sizes(rays.size(), hits.size(), stats.size());
  detail::parallel_for_rays(rays.size(), [&](std::size_t begin, std::size_t end) {
    if (stats.empty()) {
      NoStats none;
      for (std::size_t i = begin; i < end; ++i) hits[i] = trace_one<false>(rays[i], none);
    } else {
      for (std::size_t i = begin; i < end; ++i) hits[i] = trace_one<false>(rays[i], stats[i]);
    }
  });
}

template <class Derived>
void AcceleratorImpl<Derived>::occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                                        std::span<TraversalStats> stats) const {
  detail::check_batch_sizes(rays.size(), occluded.size(), stats.size());
  detail::parallel_for_rays(rays.size(), [&](std::size_t begin, std::size_t end) {
    if (stats.empty()) {
      NoStats none;
      for (std::size_t i = begin; i < end; ++i) occluded[i] = trace_one<true>(rays[i], none).found() ? 1 : 0;
    } else {
      for (std::size_t i = begin; i < end; ++i) occluded[i] = trace_one<true>(rays[i], stats[i]).found() ? 1 : 0;
    }
  });
}

}  // namespace rayaccel
