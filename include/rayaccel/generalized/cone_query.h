// The cone query (Amanatides 1984): every primitive a cone may meet, nearest first, with the fraction of the cone it
// covers: one tree walk with cone.h's conservative tests, exact triangle coverage (cone_coverage.h) accumulated front
// to back, or coverage measured on the cone's direction pattern with the single-ray kernel.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "rayaccel/core/error.h"
#include "rayaccel/core/stats.h"
#include "rayaccel/generalized/cone.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {
template <class T>
class OptionTable;
}

namespace rayaccel::generalized {

/// How a cone measures what it covers.
enum class ConeCoverage {
  /// Triangles: the exact solid-angle fraction of each (cone_coverage.h); visibility adds the candidates' fractions
  /// nearest first, each cut to what is left uncovered (Amanatides 1984), and stops once the cone is full. Scenes of
  /// other primitives use the pattern.
  analytic,
  /// The direction pattern: `samples` rays, each taking its closest hit among the candidates.
  pattern,
};

struct ConeQueryOptions {
  /// Directions of the pattern that measures coverage (cone.h), >= 1. Coverage is a multiple of 1 / samples; a
  /// primitive's estimate errs by at most the fraction of pattern cells its outline crosses.
  int samples = 256;
  ConeCoverage coverage = ConeCoverage::analytic;
};

/// The options as rows (key=value parsing and checks, as a structure's options): samples, coverage=analytic|pattern.
const OptionTable<ConeQueryOptions>& cone_query_options();

struct ConeHit {
  std::uint32_t prim_id = 0;
  /// Distance from the apex. Pattern: the smallest t at which a pattern ray hits the primitive. Analytic: the
  /// distance to the triangle where it covers the cone (cone_coverage.h). Either way, for a primitive that covers
  /// nothing (it meets the cone only between pattern rays, or may not meet it at all), the distance from the apex to
  /// its bounding box.
  float distance = 0.0f;
  /// Coverage: the fraction of the cone's solid angle whose rays hit the primitive within [t_min, t_max], as if it
  /// were alone (occlusion by other primitives is not subtracted): exact (analytic), or the fraction of pattern
  /// directions whose ray the kernel reports hitting it.
  float coverage = 0.0f;
};

/// What the cone sees. Pattern: each pattern direction's ray takes the closest hit among the candidates (ties to the
/// lower id). Analytic: the candidates in the order of their distances, each taking the part of the cone its
/// projection covers that the ones before left uncovered (cone_union.h); exact when that order is the order of depth
/// on every direction (one distance per triangle, as in Amanatides' paper: triangles that cross, or a crease seen
/// within one cone, may take each other's share).
struct ConeVisibility {
  float blocked = 0.0f;  ///< fraction of the cone blocked within the range, in [0, 1]
  /// Each primitive with a visible share of the cone (the shares sum to `blocked`), nearest first; distance as in
  /// ConeHit (pattern: its nearest hit among the rays it is the closest hit of).
  std::vector<ConeHit> visible;
};

/// Every primitive the cone may meet: conservative (a primitive hit by any ray inside the cone within its range is
/// always reported; a primitive the cone misses may be reported with coverage 0), ordered by distance, then id.
/// `stats`, when given, counts volume tests as node visits and cone/primitive tests plus pattern ray tests.
template <class View>
std::vector<ConeHit> query_cone(const View& view, const Scene& scene, const Cone& cone, const ConeQueryOptions& config,
                                TraversalStats* stats = nullptr);

/// The cone's visibility (ConeVisibility) over the candidates query_cone() would report; `stats` as there.
template <class View>
ConeVisibility cone_visibility(const View& view, const Scene& scene, const Cone& cone, const ConeQueryOptions& config,
                               TraversalStats* stats = nullptr);

namespace cone_detail {
/// The coverage and distance of each candidate, sorted (cone_query.cpp).
std::vector<ConeHit> measure(const Scene& scene, const PreparedCone& cone, std::vector<std::uint32_t> candidates,
                             const ConeQueryOptions& config, TraversalStats& stats);
ConeVisibility visibility(const Scene& scene, const PreparedCone& cone, const std::vector<std::uint32_t>& candidates,
                          const ConeQueryOptions& config, TraversalStats& stats);
void check_options(const ConeQueryOptions& config);

template <class View>
void collect(const View& view, const Scene& scene, const PreparedCone& cone, typename View::Ref ref,
             std::vector<std::uint32_t>& out, TraversalStats& stats) {
  if (view.is_leaf(ref)) {
    const bool triangles = scene.kind() == PrimitiveKind::triangles;
    view.for_each_prim(ref, [&](std::uint32_t id) {
      stats.test_primitive();
      if (triangles) {
        const auto t = scene.triangle(id);
        if (cone.triangle_outside(t[0], t[1], t[2])) return;
      } else if (cone.box_outside(scene.primitive_bounds(id), 0.0f)) {
        return;
      }
      out.push_back(id);
    });
    return;
  }
  view.for_each_child(ref, cone, stats, [&](typename View::Ref child) { collect(view, scene, cone, child, out, stats); });
}
}  // namespace cone_detail

namespace cone_detail {
/// The sorted, distinct candidates of a cone.
template <class View>
std::vector<std::uint32_t> candidates(const View& view, const Scene& scene, const PreparedCone& cone,
                                      TraversalStats& stats) {
  std::vector<std::uint32_t> out;
  if (!view.empty()) {
    stats.visit_node();
    if (!view.outside(view.root(), cone)) collect(view, scene, cone, view.root(), out, stats);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}
}  // namespace cone_detail

template <class View>
std::vector<ConeHit> query_cone(const View& view, const Scene& scene, const Cone& cone, const ConeQueryOptions& config,
                                TraversalStats* stats) {
  cone_detail::check_options(config);
  const PreparedCone prepared(cone);
  TraversalStats local;
  std::vector<ConeHit> hits =
      cone_detail::measure(scene, prepared, cone_detail::candidates(view, scene, prepared, local), config, local);
  if (stats) *stats += local;
  return hits;
}

template <class View>
ConeVisibility cone_visibility(const View& view, const Scene& scene, const Cone& cone, const ConeQueryOptions& config,
                               TraversalStats* stats) {
  cone_detail::check_options(config);
  const PreparedCone prepared(cone);
  TraversalStats local;
  ConeVisibility out =
      cone_detail::visibility(scene, prepared, cone_detail::candidates(view, scene, prepared, local), config, local);
  if (stats) *stats += local;
  return out;
}

}  // namespace rayaccel::generalized
