// The exact reference on cases whose answers are known by hand, and the library's exact edge functions
// (geometry/exact_edge.h) against GMP rationals on near-degenerate rays.
#include <gtest/gtest.h>

#include <gmpxx.h>

#include <cmath>
#include <limits>

#include "../conformance/test_scenes.h"
#include "exact_reference.h"
#include "rayaccel/geometry/exact_edge.h"

namespace rayaccel::exact {
namespace {

TriangleMesh one_triangle() {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}};
  return mesh;
}

TEST(ExactReference, HitsInsideOnEdgesAndVertices) {
  const ExactReference reference(one_triangle());
  for (const Vec3 target : {Vec3{0.25f, 0.25f, 0}, Vec3{0.5f, 0.5f, 0}, Vec3{0.5f, 0, 0}, Vec3{0, 0, 0},
                            Vec3{1, 0, 0}, Vec3{0, 0.5f, 0}}) {
    const Ray ray{{target.x, target.y, 2}, 0.0f, {0, 0, -0.5f}, 100.0f};
    const auto hits = reference.hits_past_t_min(ray);
    ASSERT_EQ(hits.size(), 1u) << target.x << ", " << target.y;
    EXPECT_EQ(hits[0].t, 4.0);  // z = 2 - 0.5 t
    EXPECT_EQ(hits[0].u, double(target.x));
    EXPECT_EQ(hits[0].v, double(target.y));
  }
}

TEST(ExactReference, MissesOneUlpOutsideAndParallelRays) {
  const ExactReference reference(one_triangle());
  const float past_half = std::nextafter(0.5f, 1.0f);
  EXPECT_TRUE(reference.hits_past_t_min({{0.5f, past_half, 1}, 0.0f, {0, 0, -1}, 10.0f}).empty());
  EXPECT_TRUE(reference.hits_past_t_min({{-1e-30f, 0.5f, 1}, 0.0f, {0, 0, -1}, 10.0f}).empty());
  EXPECT_TRUE(reference.hits_past_t_min({{0.1f, 0.1f, 0}, 0.0f, {1, 0, 0}, 10.0f}).empty());  // in the plane
  EXPECT_TRUE(reference.hits_past_t_min({{0.1f, 0.1f, 1}, 0.0f, {0, 0, 1}, 10.0f}).empty());  // pointing away
}

TEST(ExactReference, IntervalEndsAndVoidRays) {
  const ExactReference reference(one_triangle());
  const Ray at_t_min{{0.2f, 0.2f, 1}, 1.0f, {0, 0, -1}, 10.0f};
  EXPECT_TRUE(reference.hits_past_t_min(at_t_min).empty()) << "t_min < t is strict";
  const Ray ends_at_hit{{0.2f, 0.2f, 1}, 0.0f, {0, 0, -1}, 1.0f};
  const auto hits = reference.hits_past_t_min(ends_at_hit);
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_EQ(ExactReference::closest_hit_mismatch(ends_at_hit, hits, {}), std::string())
      << "a hit within its tolerance of t_max may be dropped";
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(reference.hits_past_t_min({{nan, 0.2f, 1}, 0.0f, {0, 0, -1}, 10.0f}).empty());
  EXPECT_TRUE(reference.hits_past_t_min({{0.2f, 0.2f, 1}, 0.0f, {0, 0, 0}, 10.0f}).empty());
  EXPECT_TRUE(reference.hits_past_t_min({{0.2f, 0.2f, 1}, 5.0f, {0, 0, -1}, 2.0f}).empty());
}

TEST(ExactReference, JudgesAnswers) {
  TriangleMesh mesh = one_triangle();
  mesh.vertices.push_back({0, 0, -1});
  mesh.vertices.push_back({1, 0, -1});
  mesh.vertices.push_back({0, 1, -1});
  mesh.triangles.push_back({3, 4, 5});
  const ExactReference reference(mesh);
  const Ray ray{{0.2f, 0.2f, 1}, 0.0f, {0, 0, -1}, 10.0f};
  const auto hits = reference.hits_past_t_min(ray);
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_EQ(ExactReference::closest_hit_mismatch(ray, hits, {1.0f, 0, 0.2f, 0.2f}), std::string());
  EXPECT_NE(ExactReference::closest_hit_mismatch(ray, hits, {2.0f, 1, 0.2f, 0.2f}), std::string()) << "farther";
  EXPECT_NE(ExactReference::closest_hit_mismatch(ray, hits, {1.5f, 0, 0.2f, 0.2f}), std::string()) << "wrong t";
  EXPECT_NE(ExactReference::closest_hit_mismatch(ray, hits, {}), std::string()) << "missed";
  EXPECT_EQ(ExactReference::occlusion_mismatch(ray, hits, true), std::string());
  EXPECT_NE(ExactReference::occlusion_mismatch(ray, hits, false), std::string());
}

/// E = X_p Y_q - Y_p X_q with X = A_x - (d_x / d_z) A_z, Y = A_y - (d_y / d_z) A_z, A = vertex - origin, in GMP.
int gmp_edge_sign(const Vec3& o, const Vec3& d, int kx, int ky, int kz, const Vec3& p, const Vec3& q) {
  const auto q_of = [](float f) { return mpq_class(double(f)); };
  const mpq_class sx = q_of(d[kx]) / q_of(d[kz]), sy = q_of(d[ky]) / q_of(d[kz]);
  const auto sheared = [&](const Vec3& v, mpq_class& x, mpq_class& y) {
    const mpq_class az = q_of(v[kz]) - q_of(o[kz]);
    x = q_of(v[kx]) - q_of(o[kx]) - sx * az;
    y = q_of(v[ky]) - q_of(o[ky]) - sy * az;
  };
  mpq_class px, py, qx, qy;
  sheared(p, px, py);
  sheared(q, qx, qy);
  return sgn(mpq_class(px * qy - py * qx));
}

TEST(ExactEdgeFunction, SignMatchesRationalArithmeticNearEdges) {
  conformance::Rng rng(77);
  int zeros = 0, checked = 0;
  for (int i = 0; i < 4000; ++i) {
    // Origins far and near, directions aimed at a point of the edge p-q (often exactly at a vertex), so the exact
    // edge function is zero or tiny; magnitudes from 1e-18 to 1e30.
    const float scale = std::ldexp(1.0f, static_cast<int>(rng.below(120)) - 60);
    const Vec3 p = rng.in_box({{-1, -1, -1}, {1, 1, 1}}) * scale;
    const Vec3 q = rng.in_box({{-1, -1, -1}, {1, 1, 1}}) * scale;
    const Vec3 on_edge = i % 3 == 0 ? p : p + (q - p) * rng.uniform();
    const float away = std::ldexp(1.0f, static_cast<int>(rng.below(40)));
    const Vec3 o = on_edge + rng.unit_vector() * (scale * away);
    const Vec3 d = (on_edge - o) * std::ldexp(1.0f, static_cast<int>(rng.below(40)) - 20);
    const Vec3 ad{std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)};
    if (!(ad.x + ad.y + ad.z > 0.0f) || !is_finite(o) || !is_finite(d)) continue;
    int kz = ad.x >= ad.y && ad.x >= ad.z ? 0 : (ad.y >= ad.z ? 1 : 2);
    int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
    if (d[kz] < 0.0f) std::swap(kx, ky);
    const ExactEdge e = exact_edge_function(o, d, kx, ky, kz, p, q);
    const int want = gmp_edge_sign(o, d, kx, ky, kz, p, q);
    ASSERT_EQ(e.sign, want) << "case " << i;
    EXPECT_EQ(e.value > 0.0 ? 1 : (e.value < 0.0 ? -1 : 0), want) << "case " << i;
    EXPECT_LE(e.error, std::fabs(e.value)) << "case " << i;
    zeros += want == 0 ? 1 : 0;
    ++checked;
  }
  EXPECT_GT(checked, 3900);
  EXPECT_GT(zeros, 50) << "rays through vertices must give exact zeros";
}

}  // namespace
}  // namespace rayaccel::exact
