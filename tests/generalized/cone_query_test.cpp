// The cone query against the rays it stands for: every primitive that any of thousands of random rays inside the cone
// hits is reported (over every BVH volume and the wide BVH), and coverage of a sphere matches the closed form of the
// solid angle of a spherical cap (inside the cone) and of two caps' intersection (straddling its boundary).
// Conservativeness runs over every registered variant with cone queries.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "generalized_specs.h"
#include "../shared_scenes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/generalized/generalized_rays.h"
#include "rayaccel/scene/builtin_scenes.h"
#include "rayaccel/scene/import.h"

namespace rayaccel {
namespace {

using generalized::Cone;
using generalized::ConeHit;

/// A direction uniformly distributed in solid angle within `angle` of the axis.
Vec3 random_direction(const Vec3& axis, double angle, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double s = uniform(rng);
  return generalized::cone_direction(axis, angle, s, uniform(rng));
}

/// Every primitive that any of `count` random rays inside the cone (its angle shrunk by 1e-5 so that rounding the
/// direction to float cannot leave it) hits within the range, by testing each primitive alone.
std::set<std::uint32_t> sampled_hits(const Scene& scene, const Cone& cone, int count, std::mt19937& rng) {
  std::set<std::uint32_t> out;
  const Vec3 axis = normalize(cone.axis);
  for (int i = 0; i < count; ++i) {
    const PreparedRay ray(Ray{cone.apex, cone.t_min, random_direction(axis, cone.half_angle * (1.0 - 1e-5), rng),
                              cone.t_max});
    for (std::uint32_t id = 0; id < scene.primitive_count(); ++id) {
      Hit hit = Hit::begin(ray);
      if (scene.intersect(id, ray, hit)) out.insert(id);
    }
  }
  return out;
}

class ConeConservative : public ::testing::TestWithParam<std::string> {};

TEST_P(ConeConservative, ReportsEveryPrimitiveAnyRayInsideHits) {
  const Scene scene = make_builtin_scene("soup", {{"count", "600"}});
  auto accel = make_accelerator(GetParam());
  accel->build(scene);
  const auto rays = generalized::make_generalized_rays(*accel, scene);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  const AABB box = scene.bounds();
  std::size_t hit_total = 0;
  for (int c = 0; c < 9; ++c) {
    Cone cone;
    const Vec3 e = box.extent();
    cone.apex = box.lo + Vec3{e.x * uniform(rng), e.y * uniform(rng), e.z * uniform(rng)} * 1.2f - e * 0.1f;
    const Vec3 target = box.lo + Vec3{e.x * uniform(rng), e.y * uniform(rng), e.z * uniform(rng)};
    cone.axis = target - cone.apex;
    cone.half_angle = 0.02f + 0.25f * uniform(rng);
    if (c % 3 == 1) cone.t_max = length(cone.axis) * 0.8f;
    if (c % 3 == 2) cone.t_min = length(cone.axis) * 0.3f;
    const std::vector<ConeHit> reported = rays->query_cone(cone, {.samples = 64}, nullptr);
    std::set<std::uint32_t> ids;
    for (std::size_t i = 0; i < reported.size(); ++i) {
      ids.insert(reported[i].prim_id);
      if (i > 0) {
        EXPECT_LE(reported[i - 1].distance, reported[i].distance);
      }
    }
    EXPECT_EQ(ids.size(), reported.size()) << "a primitive reported twice";
    const std::set<std::uint32_t> hit = sampled_hits(scene, cone, 1000, rng);
    hit_total += hit.size();
    for (const std::uint32_t id : hit) EXPECT_TRUE(ids.count(id)) << "cone " << c << " missed primitive " << id;
  }
  EXPECT_GT(hit_total, 50u);  // the cones met the scene, so the check had something to check
}

INSTANTIATE_TEST_SUITE_P(Conformance, ConeConservative, ::testing::ValuesIn(testing::generalized_specs()),
                         conformance::spec_test_name);

TEST(ConeConservativeShared, BunnyConesReportEveryClosestHit) {
  const auto file = testing::shared_scenes_dir() / "bunny.ply";
  RAYACCEL_NEED_SHARED_FILE(file);
  const Scene scene = load_scene(file.string());
  auto accel = make_accelerator("bvh_wide");
  accel->build(scene);
  const auto rays = generalized::make_generalized_rays(*accel, scene);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  const AABB box = scene.bounds();
  std::size_t hit_total = 0;
  for (int c = 0; c < 4; ++c) {
    Cone cone;
    cone.apex = box.center() + Vec3{uniform(rng), uniform(rng), uniform(rng)} * length(box.extent());
    cone.axis = box.center() + box.extent() * Vec3{uniform(rng), uniform(rng), uniform(rng)} * 0.3f - cone.apex;
    cone.half_angle = 0.03f + 0.05f * std::fabs(uniform(rng));
    std::set<std::uint32_t> ids;
    for (const ConeHit& h : rays->query_cone(cone, {.samples = 16})) ids.insert(h.prim_id);
    const Vec3 axis = normalize(cone.axis);
    for (int i = 0; i < 2000; ++i) {
      const Hit hit = accel->intersect(
          Ray{cone.apex, cone.t_min, random_direction(axis, cone.half_angle * (1.0 - 1e-5), rng), cone.t_max});
      if (!hit.found()) continue;
      ++hit_total;
      EXPECT_TRUE(ids.count(hit.prim_id)) << "cone " << c << " missed primitive " << hit.prim_id;
    }
  }
  EXPECT_GT(hit_total, 1000u);
}

/// Solid angle of the part of the cap of angular radius `alpha` around a direction at angle `phi` from the axis that
/// lies within `theta` of the axis: the integral over polar angle b of the arc inside the other cap (spherical law of
/// cosines), by the midpoint rule on 200000 steps (its error is far below the pattern's).
double cap_intersection(double theta, double phi, double alpha) {
  const int steps = 200000;
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) {
    const double b = (i + 0.5) * theta / steps;
    double arc;
    if (phi == 0.0 || b == 0.0) {
      arc = b <= alpha ? 2.0 * std::numbers::pi : 0.0;
    } else {
      const double c = (std::cos(alpha) - std::cos(b) * std::cos(phi)) / (std::sin(b) * std::sin(phi));
      arc = c <= -1.0 ? 2.0 * std::numbers::pi : (c >= 1.0 ? 0.0 : 2.0 * std::acos(c));
    }
    sum += arc * std::sin(b) * (theta / steps);
  }
  return sum;
}

/// The pattern's error bound: every pattern cell (solid angle omega / samples, diameter about sqrt of that times 2)
/// that the outline crosses may count wrongly; the outline is at most the two circles' perimeters long.
double pattern_bound(double theta, double alpha, int samples) {
  const double omega = 2.0 * std::numbers::pi * (1.0 - std::cos(theta));
  const double cell = 2.0 * std::sqrt(omega / samples);
  const double outline = 2.0 * std::numbers::pi * (std::sin(alpha) + std::sin(theta));
  return outline * cell / omega;
}

TEST(ConeCoverage, SphereMatchesClosedForm) {
  const double theta = 0.2;
  const int samples = 16384;
  struct SphereCase {
    double phi, alpha;  // the sphere's direction from the axis and angular radius
  };
  for (const SphereCase sc : {SphereCase{0.0, 0.15}, SphereCase{0.08, 0.05}, SphereCase{0.2, 0.1},
                              SphereCase{0.25, 0.12}, SphereCase{0.1, 0.35}}) {
    const double distance = 10.0;
    const float radius = float(distance * std::sin(sc.alpha));
    const Vec3 center{float(distance * std::sin(sc.phi)), 0.0f, float(distance * std::cos(sc.phi))};
    const Scene scene = Scene::from_spheres({Sphere{center, radius}});
    auto accel = make_accelerator("bvh:bv=sphere");
    accel->build(scene);
    const Cone cone{{0, 0, 0}, {0, 0, 1}, float(theta)};
    const auto hits = generalized::make_generalized_rays(*accel, scene)->query_cone(cone, {.samples = samples});
    ASSERT_EQ(hits.size(), 1u) << "phi " << sc.phi;
    const double omega = 2.0 * std::numbers::pi * (1.0 - std::cos(theta));
    const double expected = std::fmin(1.0, cap_intersection(theta, sc.phi, sc.alpha) / omega);
    if (sc.phi + theta <= sc.alpha) {
      EXPECT_EQ(hits[0].coverage, 1.0f);  // the sphere fills the cone: every pattern ray hits it
    } else {
      EXPECT_NEAR(hits[0].coverage, expected, pattern_bound(theta, sc.alpha, samples)) << "phi " << sc.phi;
    }
    if (sc.phi == 0.0) {  // inside: the cap's closed form, (1 - cos alpha) / (1 - cos theta)
      EXPECT_NEAR(expected, (1.0 - std::cos(sc.alpha)) / (1.0 - std::cos(theta)), 1e-6);
    }
    // Alone, the sphere's visible share and the blocked fraction are its coverage.
    const auto seen = generalized::make_generalized_rays(*accel, scene)->cone_visibility(cone, {.samples = samples});
    EXPECT_EQ(seen.blocked, hits[0].coverage);
    ASSERT_EQ(seen.visible.size(), 1u);
    EXPECT_EQ(seen.visible[0].coverage, hits[0].coverage);
    // Distance: the nearest sampled hit is at least the distance to the sphere.
    EXPECT_GE(hits[0].distance, float(distance) - radius - 1e-4f);
  }
}

TEST(ConeQuery, RejectsBadCones) {
  const Scene scene = make_builtin_scene("soup", {{"count", "10"}});
  auto accel = make_accelerator("bvh");
  accel->build(scene);
  const auto rays = generalized::make_generalized_rays(*accel, scene);
  EXPECT_THROW(rays->query_cone(Cone{{0, 0, 0}, {0, 0, 0}, 0.1f}, {}), Error);
  EXPECT_THROW(rays->query_cone(Cone{{0, 0, 0}, {0, 0, 1}, 2.0f}, {}), Error);
  EXPECT_THROW(rays->query_cone(Cone{{0, 0, 0}, {0, 0, 1}, 0.1f, 2.0f, 1.0f}, {}), Error);
  EXPECT_THROW(rays->query_cone(Cone{{0, 0, 0}, {0, 0, 1}, 0.1f}, {.samples = 0}), Error);
}

}  // namespace
}  // namespace rayaccel
