// Coverage and distance of a cone's candidates, analytic (cone_coverage.h, visibility front to back by cone_union.h)
// or on its direction pattern, and their order.
#include "rayaccel/generalized/cone_query.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <queue>
#include <string>

#include "rayaccel/accel/option_table.h"
#include "rayaccel/core/hit.h"
#include "rayaccel/generalized/cone_coverage.h"
#include "rayaccel/generalized/cone_union.h"

namespace rayaccel::generalized {

const OptionTable<ConeQueryOptions>& cone_query_options() {
  static const OptionTable<ConeQueryOptions> table = [] {
    OptionTable<ConeQueryOptions> t("cone query");
    t.choice("coverage", &ConeQueryOptions::coverage,
             {{"analytic", ConeCoverage::analytic}, {"pattern", ConeCoverage::pattern}},
             "analytic: exact solid angle per triangle, added front to back (Amanatides 1984); pattern: closest hits "
             "of `samples` rays");
    t.integer("samples", &ConeQueryOptions::samples, 1, 1 << 20, "directions of the pattern");
    return t;
  }();
  return table;
}

}  // namespace rayaccel::generalized

namespace rayaccel::generalized::cone_detail {

void check_options(const ConeQueryOptions& config) { cone_query_options().check(config); }

namespace {

bool nearer(const ConeHit& a, const ConeHit& b) {
  return a.distance < b.distance || (a.distance == b.distance && a.prim_id < b.prim_id);
}

/// Distance from p to the nearest point of the box (0 inside).
float box_distance(const Vec3& p, const AABB& box) {
  double sum = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double d = std::fmax(0.0, std::fmax(double(box.lo[a]) - p[a], double(p[a]) - box.hi[a]));
    sum += d * d;
  }
  return float(std::sqrt(sum));
}

bool analytic(const Scene& scene, const ConeQueryOptions& config) {
  return config.coverage == ConeCoverage::analytic && scene.kind() == PrimitiveKind::triangles;
}

std::optional<TriangleCoverage> cover(const Scene& scene, const PreparedCone& cone, std::uint32_t id) {
  const auto t = scene.triangle(id);
  return triangle_coverage(cone, t[0], t[1], t[2]);
}

std::vector<ConeHit> measure_analytic(const Scene& scene, const PreparedCone& cone,
                                      const std::vector<std::uint32_t>& candidates, TraversalStats& stats) {
  std::vector<ConeHit> hits;
  hits.reserve(candidates.size());
  for (const std::uint32_t id : candidates) {
    stats.test_primitive();
    const auto c = cover(scene, cone, id);
    hits.push_back(c ? ConeHit{id, c->distance, float(c->coverage)}
                     : ConeHit{id, box_distance(cone.cone().apex, scene.primitive_bounds(id)), 0.0f});
  }
  std::sort(hits.begin(), hits.end(), nearer);
  return hits;
}

/// Front to back with early termination (Amanatides 1984, with his fractional rule made exact): candidates are
/// measured in the order of a lower bound on their distance (their box's), and a measured one is settled once no
/// unmeasured candidate can be nearer, taking the part of its projection that the nearer ones leave uncovered
/// (ProjectedUnion); the measuring stops when the cone is full.
ConeVisibility visibility_analytic(const Scene& scene, const PreparedCone& cone,
                                   const std::vector<std::uint32_t>& candidates, TraversalStats& stats) {
  std::vector<std::pair<float, std::uint32_t>> order;
  order.reserve(candidates.size());
  for (const std::uint32_t id : candidates) {
    // Shrunk by far more than the rounding of either distance, so that a bound never passes the distance it bounds.
    order.emplace_back(box_distance(cone.cone().apex, scene.primitive_bounds(id)) * (1.0f - 1e-5f), id);
  }
  std::sort(order.begin(), order.end());
  struct Measured {
    ConeHit hit;
    TriangleCoverage shape;
  };
  std::vector<Measured> measured;
  const auto farther = [&](std::size_t a, std::size_t b) { return nearer(measured[b].hit, measured[a].hit); };
  std::priority_queue<std::size_t, std::vector<std::size_t>, decltype(farther)> pending(farther);
  const double half_sine = std::sin(0.5 * double(cone.cone().half_angle));
  const double total = 4.0 * std::numbers::pi * half_sine * half_sine;  // the cone's solid angle
  ProjectedUnion seen(cone.cone().half_angle);
  ConeVisibility out;
  double blocked = 0.0;
  constexpr double kFull = 1.0 - 1e-9;
  const auto settle = [&](float before) {
    while (!pending.empty() && measured[pending.top()].hit.distance < before && blocked < kFull) {
      const Measured& m = measured[pending.top()];
      pending.pop();
      const double share = std::fmin(seen.add({m.shape.polygon.data(), m.shape.count}) / total, 1.0 - blocked);
      if (!(share > 0.0)) continue;
      blocked += share;
      out.visible.push_back({m.hit.prim_id, m.hit.distance, float(share)});
    }
  };
  for (const auto& [bound, id] : order) {
    settle(bound);
    if (blocked >= kFull) break;
    stats.test_primitive();
    if (const auto c = cover(scene, cone, id)) {
      measured.push_back({{id, c->distance, float(c->coverage)}, *c});
      pending.push(measured.size() - 1);
    }
  }
  settle(std::numeric_limits<float>::infinity());
  out.blocked = float(std::fmin(blocked, 1.0));
  return out;
}

}  // namespace

std::vector<ConeHit> measure(const Scene& scene, const PreparedCone& cone, std::vector<std::uint32_t> candidates,
                             const ConeQueryOptions& config, TraversalStats& stats) {
  if (analytic(scene, config)) return measure_analytic(scene, cone, candidates, stats);
  std::vector<ConeHit> hits;
  hits.reserve(candidates.size());
  const std::vector<Vec3> pattern = cone.pattern(config.samples);
  std::vector<PreparedRay> rays;
  rays.reserve(pattern.size());
  for (const Vec3& d : pattern) rays.emplace_back(cone.ray(d));
  for (const std::uint32_t id : candidates) {
    int covered = 0;
    float nearest = std::numeric_limits<float>::infinity();
    for (const PreparedRay& ray : rays) {
      Hit hit = Hit::begin(ray);
      stats.test_primitive();
      if (scene.intersect(id, ray, hit)) {
        ++covered;
        nearest = std::fmin(nearest, hit.t);
      }
    }
    const float distance = covered > 0 ? nearest : box_distance(cone.cone().apex, scene.primitive_bounds(id));
    hits.push_back({id, distance, float(covered) / float(pattern.size())});
  }
  std::sort(hits.begin(), hits.end(), nearer);
  return hits;
}

ConeVisibility visibility(const Scene& scene, const PreparedCone& cone, const std::vector<std::uint32_t>& candidates,
                          const ConeQueryOptions& config, TraversalStats& stats) {
  if (analytic(scene, config)) return visibility_analytic(scene, cone, candidates, stats);
  ConeVisibility out;
  const std::vector<Vec3> pattern = cone.pattern(config.samples);
  std::vector<int> counts(candidates.size(), 0);
  std::vector<float> nearest(candidates.size(), std::numeric_limits<float>::infinity());
  int blocked = 0;
  for (const Vec3& d : pattern) {
    const PreparedRay ray(cone.ray(d));
    Hit hit = Hit::begin(ray);
    std::size_t closest = candidates.size();
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      stats.test_primitive();
      if (scene.intersect(candidates[i], ray, hit)) closest = i;
    }
    if (closest == candidates.size()) continue;
    ++blocked;
    ++counts[closest];
    nearest[closest] = std::fmin(nearest[closest], hit.t);
  }
  const auto total = float(pattern.size());
  out.blocked = float(blocked) / total;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (counts[i] > 0) out.visible.push_back({candidates[i], nearest[i], float(counts[i]) / total});
  }
  std::sort(out.visible.begin(), out.visible.end(), nearer);
  return out;
}

}  // namespace rayaccel::generalized::cone_detail
