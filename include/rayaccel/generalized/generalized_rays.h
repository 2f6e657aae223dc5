// Generalized rays over a built structure chosen at run time: one virtual call per image of beams or per cone, none per
// node. Supported: every Bvh<BV> (all eight volumes), the wide BVH (4 or 8 wide) and the kd-tree.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/generalized/beam_tracer.h"
#include "rayaccel/generalized/cone_query.h"

namespace rayaccel::generalized {

class GeneralizedRays {
 public:
  virtual ~GeneralizedRays() = default;
  /// trace_beams() (beam_tracer.h) over the structure, into the caller's `hits` (width * height, row by row).
  virtual BeamStats trace_beams(const PixelRays& pixels, const BeamOptions& config, std::span<Hit> hits) const = 0;
  /// The same into a new image of hits.
  BeamResult trace_beams(const PixelRays& pixels, const BeamOptions& config) const {
    return beam_detail::into_new_hits(pixels, [&](std::span<Hit> hits) { return trace_beams(pixels, config, hits); });
  }
  /// query_cone() (cone_query.h) over the structure.
  virtual std::vector<ConeHit> query_cone(const Cone& cone, const ConeQueryOptions& config,
                                          TraversalStats* stats = nullptr) const = 0;
  /// cone_visibility() (cone_query.h) over the structure.
  virtual ConeVisibility cone_visibility(const Cone& cone, const ConeQueryOptions& config,
                                         TraversalStats* stats = nullptr) const = 0;
};

/// True when make_generalized_rays() accepts this structure.
bool supports_generalized_rays(const Accelerator& accel);
/// Generalized rays over `accel`, built over `scene` (both must outlive the result). Throws Error naming the spec of a
/// structure without them (grids, octree, BSP, brute force, Embree).
std::unique_ptr<GeneralizedRays> make_generalized_rays(const Accelerator& accel, const Scene& scene);

}  // namespace rayaccel::generalized
