// Analytic cone coverage (cone_coverage.h, cone_union.h) against the rays it stands for: on fixed configurations (a
// triangle half covering the cone, a triangle behind another, one partly hidden, a cone grazing an edge, a triangle
// cut by the apex plane) the exact solid-angle fractions agree with the closest hits of a 65,536-ray pattern within
// that pattern's error bound; the union of neighbours and of folds is exact.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "rayaccel/accel/option_table.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/generalized/cone_coverage.h"
#include "rayaccel/generalized/cone_union.h"
#include "rayaccel/generalized/generalized_rays.h"

namespace rayaccel {
namespace {

using generalized::Cone;
using generalized::ConeCoverage;
using generalized::PlanePoint;

constexpr double kTheta = 0.2;
constexpr int kReferenceRays = 65536;

double cone_solid_angle(double theta) { return 2.0 * std::numbers::pi * (1.0 - std::cos(theta)); }

/// The 65,536-ray reference's error bound for one triangle edge crossing the cone: every pattern cell (solid angle
/// omega / N, diameter about twice its square root) the edge's arc crosses may be counted wrongly, and the arc inside
/// the cone is at most its diameter 2 sin(theta) long.
double reference_bound_per_edge() {
  const double omega = cone_solid_angle(kTheta);
  return 2.0 * std::sin(kTheta) * 2.0 * std::sqrt(omega / kReferenceRays) / omega;
}

TEST(ConeCoverage, DiskPolygonSolidAngleOfWholeHalfAndNone) {
  const double r = std::tan(kTheta), omega = cone_solid_angle(kTheta);
  const std::vector<PlanePoint> around{{-10, -10}, {10, -10}, {10, 10}, {-10, 10}};
  EXPECT_NEAR(generalized::disk_polygon_solid_angle(around, kTheta), omega, 1e-12 * omega);
  const std::vector<PlanePoint> half{{0, -10}, {10, -10}, {10, 10}, {0, 10}};
  EXPECT_NEAR(generalized::disk_polygon_solid_angle(half, kTheta), omega / 2.0, 1e-12 * omega);
  const std::vector<PlanePoint> clockwise{{0, 10}, {10, 10}, {10, -10}, {0, -10}};
  EXPECT_NEAR(generalized::disk_polygon_solid_angle(clockwise, kTheta), omega / 2.0, 1e-12 * omega);
  const std::vector<PlanePoint> outside{{r * 1.001, -1}, {2, -1}, {2, 1}, {r * 1.001, 1}};
  EXPECT_NEAR(generalized::disk_polygon_solid_angle(outside, kTheta), 0.0, 1e-15);
  // A small square at the centre, well inside: the solid angle of a square of side 2a at unit distance,
  // 4 asin(a^2 / (1 + a^2)) (the closed form for a rectangle seen from above its centre).
  const double a = 0.01;
  const std::vector<PlanePoint> square{{-a, -a}, {a, -a}, {a, a}, {-a, a}};
  EXPECT_NEAR(generalized::disk_polygon_solid_angle(square, kTheta), 4.0 * std::asin(a * a / (1.0 + a * a)), 1e-15);
}

struct ConeScene {
  Scene scene;
  std::unique_ptr<Accelerator> accel;
  std::unique_ptr<generalized::GeneralizedRays> rays;
};

ConeScene setup(std::vector<Vec3> vertices) {
  TriangleMesh mesh;
  mesh.vertices = std::move(vertices);
  for (std::uint32_t i = 0; i + 2 < mesh.vertices.size(); i += 3) mesh.triangles.push_back({i, i + 1, i + 2});
  ConeScene s{Scene::from_mesh(std::move(mesh)), make_accelerator("bvh"), nullptr};
  s.accel->build(s.scene);
  s.rays = generalized::make_generalized_rays(*s.accel, s.scene);
  return s;
}

const Cone kCone{{0, 0, 0}, {0, 0, 1}, float(kTheta)};

/// Each triangle's coverage alone, analytic and by the 65,536-ray pattern, within `edges` (crossing the cone) times
/// the reference's bound.
void check_coverage_alone(const ConeScene& s, int edges) {
  const auto exact = s.rays->query_cone(kCone, {});
  const auto reference = s.rays->query_cone(kCone, {.samples = kReferenceRays, .coverage = ConeCoverage::pattern});
  ASSERT_EQ(exact.size(), reference.size());
  for (const auto& e : exact) {
    for (const auto& r : reference) {
      if (r.prim_id == e.prim_id) {
        EXPECT_NEAR(e.coverage, r.coverage, edges * reference_bound_per_edge()) << e.prim_id;
      }
    }
  }
}

/// Visibility analytic and by the 65,536-ray pattern (for triangles that do not overlap in the cone, where
/// Amanatides' rule is exact): the same primitives, blocked fraction and shares within `edges` times the reference's
/// bound, and each coverage alone as check_coverage_alone(); returns the analytic visibility.
generalized::ConeVisibility check_against_reference(const ConeScene& s, int edges) {
  check_coverage_alone(s, edges);
  const auto exact = s.rays->cone_visibility(kCone, {});
  const auto reference = s.rays->cone_visibility(kCone, {.samples = kReferenceRays, .coverage = ConeCoverage::pattern});
  const double bound = edges * reference_bound_per_edge();
  EXPECT_NEAR(exact.blocked, reference.blocked, bound);
  EXPECT_EQ(exact.visible.size(), reference.visible.size());
  for (std::size_t i = 0; i < std::min(exact.visible.size(), reference.visible.size()); ++i) {
    EXPECT_EQ(exact.visible[i].prim_id, reference.visible[i].prim_id) << i;
    EXPECT_NEAR(exact.visible[i].coverage, reference.visible[i].coverage, bound) << i;
    // The analytic distance is taken along a direction inside the square around the cone's disk: between the nearest
    // hit and that hit over the cosine of the square's corner angle.
    const double corner = std::cos(std::atan(std::sqrt(2.0) * std::tan(kTheta)));
    EXPECT_GE(exact.visible[i].distance, reference.visible[i].distance * (1.0 - 1e-3));
    EXPECT_LE(exact.visible[i].distance, reference.visible[i].distance / corner * (1.0 + 1e-3));
  }
  return exact;
}

/// A triangle in the plane z = depth covering every point with x >= x0 within the cone (its other edges far away).
std::vector<Vec3> half_plane(float x0, float depth) {
  return {{x0, -100, depth}, {x0 + 200, 0, depth}, {x0, 100, depth}};
}

TEST(ConeCoverage, TriangleHalfCoveringTheCone) {
  const ConeScene s = setup(half_plane(0.0f, 10.0f));
  const auto seen = check_against_reference(s, 1);
  ASSERT_EQ(seen.visible.size(), 1u);
  EXPECT_NEAR(seen.blocked, 0.5, 1e-6);  // exact by symmetry
  // Along the centroid (r / 2, 0) of the half of the disk's square it covers.
  const double r = std::tan(kTheta);
  EXPECT_NEAR(seen.visible[0].distance, 10.0 * std::sqrt(1.0 + r * r / 4.0), 1e-4);
  const auto hits = s.rays->query_cone(kCone, {});
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_NEAR(hits[0].coverage, 0.5, 1e-6);
}

TEST(ConeCoverage, TriangleBehindAnother) {
  std::vector<Vec3> v = half_plane(0.0f, 10.0f);
  for (const Vec3& p : std::vector<Vec3>{{-100, -100, 20}, {100, -100, 20}, {0, 100, 20}}) v.push_back(p);
  const ConeScene s = setup(v);
  const auto seen = check_against_reference(s, 1);
  ASSERT_EQ(seen.visible.size(), 2u);
  EXPECT_EQ(seen.visible[0].prim_id, 0u);  // the front half first, then what is left of the full one behind
  EXPECT_NEAR(seen.visible[0].coverage, 0.5, 1e-6);
  EXPECT_NEAR(seen.visible[1].coverage, 0.5, 1e-6);
  EXPECT_FLOAT_EQ(seen.blocked, 1.0f);
  // Alone, the one behind covers all of the cone.
  const auto hits = s.rays->query_cone(kCone, {});
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_NEAR(hits[1].coverage, 1.0, 1e-6);
}

TEST(ConeCoverage, TrianglePartlyHiddenBehindAnother) {
  // The same half twice, the second one farther and wider (x >= -0.3 r): only its strip in front of nothing shows.
  // (Adding coverages without their overlap, Amanatides' simple rule, would fill the cone: 0.5 + about 0.69.)
  const float r = 20.0f * float(std::tan(kTheta));
  std::vector<Vec3> v = half_plane(0.0f, 10.0f);
  for (const Vec3& p : half_plane(-0.3f * r, 20.0f)) v.push_back(p);
  const ConeScene s = setup(v);
  const auto seen = check_against_reference(s, 2);
  ASSERT_EQ(seen.visible.size(), 2u);
  EXPECT_NEAR(seen.visible[0].coverage, 0.5, 1e-6);
  EXPECT_LT(seen.visible[1].coverage, 0.25f);
  EXPECT_LT(seen.blocked, 0.75f);
}

TEST(ConeCoverage, UnionOfNeighboursAndFolds) {
  const double omega = cone_solid_angle(kTheta);
  // Two triangles tiling a square around the disk: their shared diagonal leaves the boundary, the cone is full.
  generalized::ProjectedUnion tiles(kTheta);
  const std::vector<PlanePoint> lower{{-1, -1}, {1, -1}, {1, 1}}, upper{{-1, -1}, {1, 1}, {-1, 1}};
  const double first = tiles.add(lower);
  EXPECT_NEAR(first, omega / 2.0, 1e-12);
  EXPECT_NEAR(first + tiles.add(upper), omega, 1e-12);
  // A fold (a closed mesh's front and back faces meeting at its silhouette): the back one adds nothing, whichever
  // its orientation, and so does the same triangle again.
  generalized::ProjectedUnion fold(kTheta);
  const std::vector<PlanePoint> front{{0, -1}, {1, 0}, {0, 1}}, back{{0, 1}, {0.5, 0}, {0, -1}};
  EXPECT_NEAR(fold.add(front), omega / 2.0, 1e-12);
  EXPECT_NEAR(fold.add(back), 0.0, 1e-15);
  EXPECT_NEAR(fold.add(front), 0.0, 1e-15);
  // A triangle half behind the first: only its other half adds.
  generalized::ProjectedUnion half(kTheta);
  const std::vector<PlanePoint> whole{{-5, -5}, {5, -5}, {0, 5}};
  EXPECT_NEAR(half.add(front), omega / 2.0, 1e-12);
  EXPECT_NEAR(half.add(whole), omega / 2.0, 1e-12);
}

TEST(ConeCoverage, ConeGrazingAnEdge) {
  const float r = 10.0f * float(std::tan(kTheta));
  for (const float x0 : {0.9f * r, 0.99f * r}) {
    const ConeScene s = setup(half_plane(x0, 10.0f));
    const auto seen = check_against_reference(s, 1);
    // The cap segment beyond x0, as a solid angle: positive and small.
    EXPECT_GT(seen.blocked, 0.0f);
    EXPECT_LT(seen.blocked, 0.06f);
  }
  // An edge just outside the cone: no coverage, and the reference agrees.
  const ConeScene s = setup(half_plane(1.0001f * r, 10.0f));
  const auto seen = check_against_reference(s, 0);
  EXPECT_EQ(seen.blocked, 0.0f);
  EXPECT_TRUE(seen.visible.empty());
}

TEST(ConeCoverage, TrianglesThroughTheApexPlaneAndOblique) {
  // One triangle reaching behind the apex (clipped at the apex plane), one tilted across the axis.
  const ConeScene s = setup({{-1, 0.5f, -5}, {3, -0.2f, 12}, {-2, 4, 12}, {-4, -4, 30}, {4, -3, 36}, {0.5f, 5, 24}});
  check_coverage_alone(s, 6);
  const auto hits = s.rays->query_cone(kCone, {});
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_GT(hits[0].coverage, 0.0f);
  EXPECT_GT(hits[1].coverage, 0.0f);
}

TEST(ConeCoverage, OptionsAreRowsOfAnOptionTable) {
  const auto& table = generalized::cone_query_options();
  EXPECT_NO_THROW(table.check({}));
  EXPECT_THROW(table.check({.samples = 0}), Error);
  bool has_coverage = false;
  for (const OptionSpec& spec : table.specs()) has_coverage = has_coverage || spec.key == "coverage";
  EXPECT_TRUE(has_coverage);
}

}  // namespace
}  // namespace rayaccel
