// The exact domain (exact_domain.h): which rays the differential fuzzer checks against the exact reference. Inside
// it brute force must agree with the reference; just outside it, on each side the predicate guards, the library's
// float answer cannot be the exact one (a t or a coordinate that float cannot hold), which is why the ray is left out.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "exact_domain.h"
#include "exact_reference.h"
#include "rayaccel/accel/registry.h"

namespace rayaccel::exact {
namespace {

/// One triangle across the z axis at depth z, with corners at distance `size` from the axis.
TriangleMesh triangle_at(float z, float size) {
  TriangleMesh mesh;
  mesh.vertices = {{-size, -size, z}, {size, -size, z}, {0.0f, size, z}};
  mesh.triangles = {{0, 1, 2}};
  return mesh;
}

Ray make_ray(Vec3 origin, Vec3 direction, float t_min = 0.0f, float t_max = std::numeric_limits<float>::infinity()) {
  return {origin, t_min, direction, t_max};
}

/// The exact reference's verdict on brute force's answers for `ray` (empty when they agree).
std::string brute_force_against_exact(const TriangleMesh& mesh, const Ray& ray) {
  const Scene scene = Scene::from_mesh(mesh, "one");
  auto brute = make_accelerator("brute_force");
  brute->build(scene);
  const Ray read = ray_as_read(ray);
  const auto hits = ExactReference(mesh).hits_past_t_min(read);
  const std::string fault = ExactReference::closest_hit_mismatch(read, hits, brute->intersect(ray));
  return fault.empty() ? ExactReference::occlusion_mismatch(read, hits, brute->occluded(ray)) : fault;
}

TEST(ExactDomain, OrdinaryAndVoidRaysAreInside) {
  const TriangleMesh mesh = triangle_at(5.0f, 1.0f);
  for (const Ray& ray : {make_ray({0, 0, 0}, {0, 0, 1}), make_ray({0.1f, 0.2f, -1e6f}, {0, 0, 1e-6f}),
                         make_ray({0, 0, 0}, {0, 0, 0}), make_ray({NAN, 0, 0}, {0, 0, 1}),
                         make_ray({0, 0, 0}, {0, 0, 1}, 2.0f, 1.0f)}) {
    EXPECT_EQ(exact_domain(ray, mesh), DomainVerdict::inside);
    EXPECT_EQ(brute_force_against_exact(mesh, ray), "");
  }
}

TEST(ExactDomain, SubnormalDirectionComponentsReadAsSignedZero) {
  const Ray read = ray_as_read(make_ray({0, 0, 0}, {1e-40f, -1e-40f, std::numeric_limits<float>::min()}));
  EXPECT_EQ(read.direction.x, 0.0f);
  EXPECT_FALSE(std::signbit(read.direction.x));
  EXPECT_EQ(read.direction.y, 0.0f);
  EXPECT_TRUE(std::signbit(read.direction.y));
  EXPECT_EQ(read.direction.z, std::numeric_limits<float>::min()) << "the smallest normal float is read as it is";
  // A ray whose subnormal x component would carry it 1e-40 * 5e37 = 5e-3 past the triangle's corner: as read, it
  // goes straight to the corner and hits it, and the reference, given the ray as read, agrees.
  const TriangleMesh mesh = triangle_at(5e37f, 1.0f);
  const Ray ray = make_ray({-1.0f, -1.0f, 0.0f}, {-1e-40f, 0.0f, 1.0f});
  EXPECT_EQ(exact_domain(ray, mesh), DomainVerdict::inside);
  EXPECT_EQ(brute_force_against_exact(mesh, ray), "");
}

/// A triangle 2 * size wide at z = 1 with a corner at (-size, -1, 1).
TriangleMesh wide_triangle(float size) {
  TriangleMesh mesh;
  mesh.vertices = {{size, -1.0f, 1.0f}, {-size, -1.0f, 1.0f}, {0.0f, 1.0f, 1.0f}};
  mesh.triangles = {{0, 1, 2}};
  return mesh;
}

TEST(ExactDomain, CoordinatesBeyondHalfOfFloatRangeAreOutside) {
  // Seen from its corner at -2e38, the far corner is 4e38 across the ray: the kernel's float difference overflows
  // to infinity, and brute force misses the corner the exact reference sees hit.
  const Ray corner = make_ray({-2e38f, -1.0f, 0.0f}, {0, 0, 1});
  EXPECT_EQ(exact_domain(corner, wide_triangle(2e38f)), DomainVerdict::coordinate_out_of_range);
  EXPECT_NE(brute_force_against_exact(wide_triangle(2e38f), corner), "");
  // At 8e37 across (under 2^126) it is inside, and there brute force is exact.
  const Ray nearer_corner = make_ray({-4e37f, -1.0f, 0.0f}, {0, 0, 1});
  EXPECT_EQ(exact_domain(nearer_corner, wide_triangle(4e37f)), DomainVerdict::inside);
  EXPECT_EQ(brute_force_against_exact(wide_triangle(4e37f), nearer_corner), "");
}

TEST(ExactDomain, DepthsInUnitsOfTOutsideFloatRangeAreOutside) {
  // A triangle 1e10 away along a direction 1e-30 long is hit at t = 1e40, past float's range: brute force cannot
  // report it, the exact reference finds it.
  const TriangleMesh far_away = triangle_at(1e10f, 1e9f);
  const Ray slow = make_ray({0, 0, 0}, {0, 0, 1e-30f});
  EXPECT_EQ(exact_domain(slow, far_away), DomainVerdict::depth_out_of_range);
  EXPECT_NE(brute_force_against_exact(far_away, slow), "");
  // A triangle 1e-20 away along a direction 1e30 long is hit at t = 1e-50, under float's range.
  const TriangleMesh near = triangle_at(1e-20f, 1e-20f);
  const Ray fast = make_ray({0, 0, 0}, {0, 0, 1e30f});
  EXPECT_EQ(exact_domain(fast, near), DomainVerdict::depth_out_of_range);
  EXPECT_NE(brute_force_against_exact(near, fast), "");
  // Within range on both sides, brute force is exact.
  const Ray moderate = make_ray({0, 0, 0}, {0, 0, 1e-20f});
  EXPECT_EQ(exact_domain(moderate, far_away), DomainVerdict::inside);
  EXPECT_EQ(brute_force_against_exact(far_away, moderate), "");
  // Depth 0 (vertices in the plane across the ray at its origin) is no underflow: hit at t = 0 exactly.
  const TriangleMesh through_origin = triangle_at(0.0f, 1.0f);
  const Ray from_inside = make_ray({0, 0, 0}, {0, 0, 1}, -1.0f);
  EXPECT_EQ(exact_domain(from_inside, through_origin), DomainVerdict::inside);
  EXPECT_EQ(brute_force_against_exact(through_origin, from_inside), "");
}

TEST(ExactDomain, TiedDominantAxesAreAllChecked) {
  // |d_x| = |d_y|: the kernel may take either as the depth axis, so both depths must be in range. The vertices'
  // y is 0, 1e-35 from the origin: a depth of 1e-35 in units of t along y.
  TriangleMesh mesh;
  mesh.vertices = {{1.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 1.0f}, {2.0f, 0.0f, 0.0f}};
  mesh.triangles = {{0, 1, 2}};
  EXPECT_EQ(exact_domain(make_ray({0.0f, 1e-35f, 0.0f}, {1, 1, 0}), mesh), DomainVerdict::depth_out_of_range);
  EXPECT_EQ(exact_domain(make_ray({0.0f, 1e-35f, 0.0f}, {1, 0.5f, 0}), mesh), DomainVerdict::inside);
}

TEST(ExactDomain, UnderflowingShearsAreInsideAndDecidedExactly) {
  // The fuzz input of corpus shear-underflow-grazing-ray: d_z / d_y = 6e-50 underflows float's shear to 0. Its error
  // bound was relative to the shear, so 0 too, and brute force missed a grazing hit the reference finds at
  // t = 0.99996; the bound now has an absolute part (kShearAbsoluteError), and the answer is exact.
  TriangleMesh mesh;
  mesh.vertices = {{0x1.21206cp-36f, -0x1.ed3da8p+83f, -0x1.a18cb6p-76f},
                   {-0x1.7p+1f, 0x1.196d78p+88f, -0x1.31acc6p-89f},
                   {-0x1.5p+1f, 0x1.4p+0f, 0x0p+0f}};
  mesh.triangles = {{0, 1, 2}};
  const Ray grazing = make_ray({-0x1.7p+1f, 0x1.196d78p+88f, 0.0f}, {0x1.7p+1f, -0x1.28d766p+88f, -0x1.a18cb6p-76f});
  EXPECT_EQ(exact_domain(grazing, mesh), DomainVerdict::inside);
  EXPECT_EQ(brute_force_against_exact(mesh, grazing), "");
}

TEST(ExactDomain, TrianglesThatAreNeverHitDoNotCount) {
  // A triangle with an infinite or NaN vertex is never hit, whatever its other vertices: it does not put the ray
  // outside, even with a vertex 3e38 away.
  TriangleMesh mesh = triangle_at(5.0f, 1.0f);
  mesh.vertices.push_back({std::numeric_limits<float>::infinity(), 0.0f, 0.0f});
  mesh.vertices.push_back({3e38f, 0.0f, 0.0f});
  mesh.vertices.push_back({NAN, 0.0f, 0.0f});
  mesh.triangles.push_back({3, 4, 0});
  mesh.triangles.push_back({5, 4, 1});
  const Ray ray = make_ray({0, 0, 0}, {0, 0, 1});
  EXPECT_EQ(exact_domain(ray, mesh), DomainVerdict::inside);
  EXPECT_EQ(brute_force_against_exact(mesh, ray), "");
  // A finite one that far away does.
  mesh.triangles.push_back({4, 1, 2});
  EXPECT_EQ(exact_domain(ray, mesh), DomainVerdict::coordinate_out_of_range);
}

}  // namespace
}  // namespace rayaccel::exact
