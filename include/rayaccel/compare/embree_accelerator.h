// EmbreeAccelerator: Intel Embree 3 behind the Accelerator interface for benchmark comparisons only (the registry's
// "embree" comparison entry), in the rayaccel::compare target, which alone defines RAYACCEL_HAVE_EMBREE.
#pragma once

#include <vector>

#include "rayaccel/accel/registry.h"

namespace rayaccel {

/// Adds "embree" (a comparison entry) where Embree was found at build time; nothing otherwise.
void register_embree(std::vector<AcceleratorInfo>& registry);
/// Makes "embree" a registry entry in a program that links rayaccel::compare: call before anything uses the
/// registry (add_registry_hook()).
void enable_embree_comparison();

}  // namespace rayaccel

#ifdef RAYACCEL_HAVE_EMBREE

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/option_table.h"

namespace rayaccel {

enum class EmbreeBuildQuality { low, medium, high };

struct EmbreeOptions {
  int threads = 0;                                          ///< Embree worker threads; 0 = Embree's default
  EmbreeBuildQuality quality = EmbreeBuildQuality::medium;  ///< RTC_BUILD_QUALITY_*; medium is Embree's default
  bool robust = false;  ///< RTC_SCENE_FLAG_ROBUST: Embree's watertight mode, the closest to rayaccel's guarantees
  /// RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION: the queries with a QueryContext run through an intersection filter on
  /// the context (without it they throw Error, so the plain queries are timed with Embree's default flags).
  bool context_filter = false;
};

/// Embree over a triangle scene. Hits follow this library's rules: t_min < t <= t_max, a miss is {t = +inf,
/// prim_id = kInvalidPrimId, u = v = 0}, and void rays (NaN, infinite or zero direction, see PreparedRay) miss
/// without reaching Embree. Traversal statistics are not available: the stats overloads leave them unchanged.
/// Batches run with flush-to-zero and denormals-are-zero set, as Embree's documentation recommends for speed (so a
/// subnormal ray component reads as zero there); single-ray calls run in the caller's floating-point environment.
/// Embree's options: key, member, range and doc of each (the registry's options, their parsing and checks).
const OptionTable<EmbreeOptions>& embree_option_table();

class EmbreeAccelerator final : public Accelerator {
 public:
  /// Checks the options (embree_option_table()) and creates the Embree device; throws Error naming a bad option, or
  /// with Embree's message when the device cannot be made.
  explicit EmbreeAccelerator(EmbreeOptions options = {});
  ~EmbreeAccelerator() override;
  EmbreeAccelerator(const EmbreeAccelerator&) = delete;
  EmbreeAccelerator& operator=(const EmbreeAccelerator&) = delete;

  /// Throws Error "embree comparison supports triangle scenes only" for sphere or user scenes.
  void build(const Scene& scene) override;

  Hit intersect(const Ray& ray) const override;
  Hit intersect(const Ray& ray, TraversalStats& stats) const override;
  bool occluded(const Ray& ray) const override;
  bool occluded(const Ray& ray, TraversalStats& stats) const override;
  void intersect(std::span<const Ray> rays, std::span<Hit> hits, std::span<TraversalStats> stats = {}) const override;
  void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                std::span<TraversalStats> stats = {}) const override;
  /// Queries with a QueryContext, with options.context_filter only (else Error): Embree's context filter rejects a
  /// candidate hit the context rules out (skip, masks, primitive switches: the rules of ContextStats, which rayaccel's
  /// leaves apply before their exact test) or its filter rejects, and Embree's traversal goes on, as in Embree's own
  /// next-hit and alpha-test examples.
  Hit intersect(const QueryContext& context, const Ray& ray, std::size_t ray_index = 0) const override;
  bool occluded(const QueryContext& context, const Ray& ray, std::size_t ray_index = 0) const override;
  void intersect(const QueryContext& context, std::span<const Ray> rays, std::span<Hit> hits) const override;
  void occluded(const QueryContext& context, std::span<const Ray> rays,
                std::span<std::uint8_t> occluded) const override;
  /// Embree's 8-wide packets: each run rays[8k .. 8k + 8) goes through one rtcIntersect8 call (the intersect
  /// context flagged coherent), in the batch loop and floating-point mode of intersect(rays, hits), with its hit
  /// rules. Void rays and rays with an empty interval are inactive lanes and miss; a final partial packet has its
  /// missing lanes inactive; a packet with no active lane does not reach Embree.
  using Accelerator::intersect_packets;  // the context forms: Embree's context filter, ray by ray
  using Accelerator::occluded_packets;
  void intersect_packets(std::span<const Ray> rays, std::span<Hit> hits) const override;
  /// The same with rtcOccluded8 for any hits: 1 for a lane Embree reports occluded, 0 for the others (inactive lanes
  /// included).
  void occluded_packets(std::span<const Ray> rays, std::span<std::uint8_t> occluded) const override;

  /// Bytes Embree allocated for the committed scene, as reported by its device memory monitor.
  std::size_t memory_bytes() const override;
  /// Embree's geometry buffers: the padded vertex copy and the index buffer of the valid triangles.
  std::size_t input_memory_bytes(const Scene& scene) const override;
  std::vector<BuildStatistic> build_statistics() const override;
  std::vector<std::string> validate() const override;

 private:
  struct State;
  std::unique_ptr<State> state_;

};

}  // namespace rayaccel

#endif  // RAYACCEL_HAVE_EMBREE
