// The runtime choice of a structure view for beams and cones: one dynamic_cast per structure, then templates.
#include "rayaccel/generalized/generalized_rays.h"

#include <string>

#include "rayaccel/bv/aabb_volume.h"
#include "rayaccel/bv/capsule_volume.h"
#include "rayaccel/bv/hull_volume.h"
#include "rayaccel/bv/kdop_volume.h"
#include "rayaccel/bv/obb_volume.h"
#include "rayaccel/bv/sphere_volume.h"
#include "rayaccel/core/error.h"
#include "rayaccel/generalized/frustum_tracer.h"
#include "rayaccel/generalized/structure_views.h"

namespace rayaccel::generalized {

namespace {

template <class View>
class ViewRays final : public GeneralizedRays {
 public:
  ViewRays(View view, const Scene& scene) : view_(view), scene_(scene) {}
  using GeneralizedRays::trace_beams;
  BeamStats trace_beams(const PixelRays& pixels, const BeamOptions& config, std::span<Hit> hits) const override {
    if constexpr (requires { trace_frustum_beams(view_, pixels, config, hits); }) {
      if (config.frustum) return trace_frustum_beams(view_, pixels, config, hits);
    }
    return generalized::trace_beams(view_, scene_, pixels, config, hits);
  }
  std::vector<ConeHit> query_cone(const Cone& cone, const ConeQueryOptions& config,
                                  TraversalStats* stats) const override {
    return generalized::query_cone(view_, scene_, cone, config, stats);
  }
  ConeVisibility cone_visibility(const Cone& cone, const ConeQueryOptions& config,
                                 TraversalStats* stats) const override {
    return generalized::cone_visibility(view_, scene_, cone, config, stats);
  }

 private:
  View view_;
  const Scene& scene_;
};

template <class BV>
std::unique_ptr<GeneralizedRays> try_bvh(const Accelerator& accel, const Scene& scene) {
  if (const auto* bvh = dynamic_cast<const Bvh<BV>*>(&accel)) {
    return std::make_unique<ViewRays<BvhView<BV>>>(BvhView<BV>(*bvh), scene);
  }
  return nullptr;
}

std::unique_ptr<GeneralizedRays> try_make(const Accelerator& accel, const Scene& scene) {
  if (const auto* kd = dynamic_cast<const KdTree*>(&accel)) {
    return std::make_unique<ViewRays<KdView>>(KdView(*kd), scene);
  }
  if (const auto* wide = dynamic_cast<const wide::WideBvh*>(&accel)) {
    if (wide->width() == 8) return std::make_unique<ViewRays<WideView<8>>>(WideView<8>(*wide), scene);
    return std::make_unique<ViewRays<WideView<4>>>(WideView<4>(*wide), scene);
  }
  std::unique_ptr<GeneralizedRays> out;
  (void)((out = try_bvh<AabbVolume>(accel, scene)) || (out = try_bvh<SphereVolume>(accel, scene)) ||
         (out = try_bvh<ObbVolume>(accel, scene)) || (out = try_bvh<Kdop14Volume>(accel, scene)) ||
         (out = try_bvh<Kdop18Volume>(accel, scene)) || (out = try_bvh<Kdop26Volume>(accel, scene)) ||
         (out = try_bvh<HullVolume>(accel, scene)) || (out = try_bvh<CapsuleVolume>(accel, scene)));
  return out;
}

}  // namespace

bool supports_generalized_rays(const Accelerator& accel) {
  static const Scene empty;
  return try_make(accel, empty) != nullptr;
}

std::unique_ptr<GeneralizedRays> make_generalized_rays(const Accelerator& accel, const Scene& scene) {
  std::unique_ptr<GeneralizedRays> out = try_make(accel, scene);
  if (!out) {
    throw Error("generalized rays: structure '" + accel.spec() +
                "' has no beam or cone traversal (use bvh with any bv, bvh_wide or kdtree)");
  }
  return out;
}

}  // namespace rayaccel::generalized
