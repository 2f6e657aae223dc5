// Two uses of cones in the renderer (Amanatides 1984): soft shadows from a spherical light and anti-aliasing, each
// beside the many-ray estimate of the same integral it replaces, so their errors compare directly.
#pragma once

#include <cstdint>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/core/stats.h"
#include "rayaccel/generalized/cone_query.h"
#include "rayaccel/render/camera.h"
#include "rayaccel/render/image.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {

enum class ConeEffect { soft_shadows, anti_aliasing };
/// Parses "shadows" or "aa"; throws Error naming both otherwise.
ConeEffect parse_cone_effect(std::string_view text);

struct ConeEffectSettings {
  int width = 512;
  int height = 512;
  ConeEffect effect = ConeEffect::soft_shadows;
  /// How each cone measures coverage: exact per triangle, added front to back (the default), or on its pattern.
  generalized::ConeCoverage coverage = generalized::ConeCoverage::analytic;
  int cone_samples = 64;  ///< coverage=pattern: directions of each cone's pattern (generalized/cone.h), >= 1
  /// > 0: the many-ray estimate instead, this many random rays per cone (shadow rays, or camera rays per pixel).
  int rays = 0;
  float light_radius_fraction = 0.05f;  ///< soft shadows: the light's radius over the scene box diagonal, > 0
  std::uint64_t seed = 1;               ///< random rays: the same seed gives the same image
};

struct ConeEffectResult {
  Image image;
  double milliseconds = 0.0;  ///< wall time of the effect's queries (cones or rays), primary rays excluded
  TraversalStats cost;        ///< the effect's node visits and primitive tests (cone candidates and pattern tests)
  std::uint64_t queries = 0;  ///< cones queried, or rays traced
};

/// Renders the effect through `accel` (built over `scene`); cones need bvh, bvh_wide or kdtree (else Error naming the spec).
/// Soft shadows: grey = sRGB of 0.05 + 0.75 * unblocked * cos(angle to the light) at primary hits, the light from
/// default_lights(). Anti-aliasing: normal colours (as the normals mode) over the pixel's cone, background where no
/// primitive is hit. Throws Error for a bad size, samples or radius.
ConeEffectResult render_cone_effect(const Accelerator& accel, const Scene& scene, const Camera& camera,
                                    const ConeEffectSettings& settings);

}  // namespace rayaccel
