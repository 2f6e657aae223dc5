// Coverage and distance of a cone's candidates on its direction pattern, and their order.
#include "rayaccel/generalized/cone_query.h"

#include <cmath>
#include <limits>
#include <string>

#include "rayaccel/accel/option_table.h"
#include "rayaccel/core/hit.h"

namespace rayaccel::generalized::cone_detail {

void check_options(const ConeQueryOptions& config) {
  static const OptionTable<ConeQueryOptions> table = [] {
    OptionTable<ConeQueryOptions> t("cone query");
    t.integer("samples", &ConeQueryOptions::samples, 1, std::numeric_limits<int>::max(),
              "directions of the pattern that measures coverage");
    return t;
  }();
  table.check(config);
}

namespace {

/// Distance from p to the nearest point of the box (0 inside).
float box_distance(const Vec3& p, const AABB& box) {
  double sum = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double d = std::fmax(0.0, std::fmax(double(box.lo[a]) - p[a], double(p[a]) - box.hi[a]));
    sum += d * d;
  }
  return float(std::sqrt(sum));
}

}  // namespace

std::vector<ConeHit> measure(const Scene& scene, const PreparedCone& cone, std::vector<std::uint32_t> candidates,
                             const ConeQueryOptions& config, TraversalStats& stats) {
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
  std::sort(hits.begin(), hits.end(), [](const ConeHit& a, const ConeHit& b) {
    return a.distance < b.distance || (a.distance == b.distance && a.prim_id < b.prim_id);
  });
  return hits;
}

ConeVisibility visibility(const Scene& scene, const PreparedCone& cone, const std::vector<std::uint32_t>& candidates,
                          const ConeQueryOptions& config, TraversalStats& stats) {
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
  std::sort(out.visible.begin(), out.visible.end(), [](const ConeHit& a, const ConeHit& b) {
    return a.distance < b.distance || (a.distance == b.distance && a.prim_id < b.prim_id);
  });
  return out;
}

}  // namespace rayaccel::generalized::cone_detail
