// The beam's conservative tests against the rays inside it: a box, ball or triangle declared outside is met by none of
// hundreds of rays spread over the beam (exact segment/box and point/ball distances in double, the watertight kernel
// for triangles), while many are declared outside (the tests are not vacuous); a triangle proven in front is hit
// before the back triangle by every sampled ray that hits both, by the computed t.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "rayaccel/generalized/beam.h"
#include "rayaccel/geometry/ray_triangle.h"

namespace rayaccel {
namespace {

using generalized::Beam;
using generalized::DVec3;

struct RandomBeam {
  Beam beam;
  std::vector<Vec3> directions;  ///< rays inside: convex combinations of the edges, rounded to float (kept if inside)
};

RandomBeam random_beam(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const Vec3 apex{u(rng) * 3, u(rng) * 3, u(rng) * 3};
  const Vec3 axis = normalize(Vec3{u(rng), u(rng), u(rng)});
  const Vec3 a = normalize(cross(axis, std::fabs(axis.x) < 0.5f ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
  const Vec3 b = cross(axis, a);
  const float w = 0.02f + 0.3f * (u(rng) + 1.0f), h = 0.02f + 0.3f * (u(rng) + 1.0f);
  DVec3 edges[4];
  const float su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
  for (int i = 0; i < 4; ++i) edges[i] = generalized::to_d(axis + a * (su[i] * w) + b * (sv[i] * h));
  RandomBeam out{Beam::through(apex, edges, 4), {}};
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < 400; ++k) {
    double weight[4], sum = 0;
    for (double& x : weight) sum += (x = unit(rng) * unit(rng));
    DVec3 d{0, 0, 0};
    for (int i = 0; i < 4; ++i) {
      d = {d.x + edges[i].x * weight[i] / sum, d.y + edges[i].y * weight[i] / sum, d.z + edges[i].z * weight[i] / sum};
    }
    const Vec3 f{float(d.x), float(d.y), float(d.z)};
    if (out.beam.contains(f)) out.directions.push_back(f);
  }
  // The beam's own edges, nudged inward, reach its corners.
  for (int i = 0; i < 4; ++i) {
    const Vec3 f = normalize(axis + a * (su[i] * w * 0.999f) + b * (sv[i] * h * 0.999f));
    if (out.beam.contains(f)) out.directions.push_back(f);
  }
  return out;
}

/// True when the ray apex + t d (t >= 0) meets the closed box: the slab test in double.
bool ray_meets_box(const Vec3& o, const Vec3& d, const AABB& box) {
  double t0 = 0.0, t1 = INFINITY;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0f) {
      if (o[a] < box.lo[a] || o[a] > box.hi[a]) return false;
      continue;
    }
    double n = (double(box.lo[a]) - o[a]) / d[a], f = (double(box.hi[a]) - o[a]) / d[a];
    if (n > f) std::swap(n, f);
    t0 = std::max(t0, n);
    t1 = std::min(t1, f);
  }
  return t0 <= t1;
}

/// True when the ray passes within r of c (distance of the half-line to the point, in double).
bool ray_meets_ball(const Vec3& o, const Vec3& d, const Vec3& c, float r) {
  const DVec3 oc{double(c.x) - o.x, double(c.y) - o.y, double(c.z) - o.z};
  const DVec3 dd{d.x, d.y, d.z};
  const double t = std::max(0.0, detail::ddot(oc, dd) / detail::ddot(dd, dd));
  const DVec3 p{oc.x - t * dd.x, oc.y - t * dd.y, oc.z - t * dd.z};
  return std::sqrt(detail::ddot(p, p)) <= r;
}

TEST(Beam, OutsideTestsAreConservativeAndNotVacuous) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int boxes_out = 0, boxes_met = 0, balls_out = 0, balls_met = 0, tris_out = 0, tris_met = 0;
  for (int b = 0; b < 60; ++b) {
    const RandomBeam rb = random_beam(rng);
    ASSERT_TRUE(rb.beam.valid());
    ASSERT_GT(rb.directions.size(), 300u);
    const Vec3 apex = rb.beam.apex;
    for (int k = 0; k < 60; ++k) {
      const Vec3 c{u(rng) * 5, u(rng) * 5, u(rng) * 5};
      const Vec3 e{0.05f + std::fabs(u(rng)), 0.05f + std::fabs(u(rng)), 0.05f + std::fabs(u(rng))};
      const AABB box{c - e * 0.5f, c + e * 0.5f};
      const bool box_out = rb.beam.box_outside(box, 0.0f);
      const float radius = 0.05f + std::fabs(u(rng));
      const bool ball_out = rb.beam.sphere_outside(c, radius);
      const Vec3 t0 = c + Vec3{u(rng), u(rng), u(rng)}, t1 = c + Vec3{u(rng), u(rng), u(rng)};
      const bool tri_out = rb.beam.triangle_outside(c, t0, t1);
      boxes_out += box_out;
      balls_out += ball_out;
      tris_out += tri_out;
      bool box_hit = false, ball_hit = false, tri_hit = false;
      for (const Vec3& d : rb.directions) {
        box_hit = box_hit || ray_meets_box(apex, d, box);
        ball_hit = ball_hit || ray_meets_ball(apex, d, c, radius);
        const PreparedRay ray(Ray{apex, 0.0f, d});
        Hit hit = Hit::begin(ray);
        tri_hit = tri_hit || intersect_triangle(ray, c, t0, t1, 0, hit);
      }
      boxes_met += box_hit;
      balls_met += ball_hit;
      tris_met += tri_hit;
      EXPECT_FALSE(box_out && box_hit) << "beam " << b << " box " << k;
      EXPECT_FALSE(ball_out && ball_hit) << "beam " << b << " ball " << k;
      EXPECT_FALSE(tri_out && tri_hit) << "beam " << b << " triangle " << k;
    }
  }
  // Both outcomes occur often, so the checks above are not vacuous.
  for (const int n : {boxes_out, boxes_met, balls_out, balls_met, tris_out, tris_met}) EXPECT_GT(n, 100);
}

TEST(Beam, FrontTriangleIsHitFirstByEveryRay) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int proven = 0, pairs_checked = 0;
  for (int b = 0; b < 60; ++b) {
    const RandomBeam rb = random_beam(rng);
    const Vec3 apex = rb.beam.apex;
    const Vec3 axis = normalize(rb.directions[0]);
    for (int k = 0; k < 30; ++k) {
      // A large front triangle across the beam at distance s, a small one behind it at distance s + gap (proven only
      // when the gap clears the margin: about a thirtieth of the two triangles' sizes).
      const float s = 2.0f + 3.0f * std::fabs(u(rng)), gap = 3.0f * std::fabs(u(rng));
      const Vec3 side = normalize(cross(axis, Vec3{u(rng), u(rng), u(rng)}));
      const Vec3 up = cross(axis, side) * (1.0f + 0.3f * u(rng));
      const Vec3 f0 = apex + axis * s + side * 4.0f, f1 = apex + axis * s - side * 2.0f + up * 4.0f,
                 f2 = apex + axis * s - side * 2.0f - up * 4.0f;
      const Vec3 c = apex + axis * (s + gap);
      const Vec3 b0 = c + Vec3{u(rng), u(rng), u(rng)} * 0.3f, b1 = c + Vec3{u(rng), u(rng), u(rng)} * 0.3f,
                 b2 = c + Vec3{u(rng), u(rng), u(rng)} * 0.3f;
      AABB back;
      back.extend(b0).extend(b1).extend(b2);
      if (!generalized::beam_front_of(rb.beam, f0, f1, f2, back)) continue;
      ++proven;
      for (const Vec3& d : rb.directions) {
        const PreparedRay ray(Ray{apex, 0.0f, d});
        Hit front = Hit::begin(ray), behind = Hit::begin(ray);
        if (intersect_triangle(ray, f0, f1, f2, 0, front) && intersect_triangle(ray, b0, b1, b2, 1, behind)) {
          ++pairs_checked;
          EXPECT_LT(front.t, behind.t) << "beam " << b << " pair " << k;
        }
      }
    }
  }
  EXPECT_GT(proven, 50);
  EXPECT_GT(pairs_checked, 1000);
}

TEST(Beam, DegenerateEdgesMakeAnInvalidBeam) {
  const DVec3 parallel[4] = {{0, 0, 1}, {0, 0, 1}, {0.1, 0, 1}, {0, 0.1, 1}};
  EXPECT_FALSE(Beam::through({0, 0, 0}, parallel, 4).valid());
  const DVec3 reflex[4] = {{-0.1, -0.1, 1}, {0.1, 0.1, 1}, {0.1, -0.1, 1}, {-0.1, 0.1, 1}};  // crossed quad
  EXPECT_FALSE(Beam::through({0, 0, 0}, reflex, 4).valid());
  const DVec3 nan[3] = {{0, 0, 1}, {NAN, 0, 1}, {0, 0.1, 1}};
  EXPECT_FALSE(Beam::through({0, 0, 0}, nan, 3).valid());
  const Beam invalid = Beam::through({0, 0, 0}, parallel, 4);
  EXPECT_FALSE(invalid.box_outside(AABB{{5, 5, 5}, {6, 6, 6}}, 0.0f));  // an invalid beam proves nothing
  EXPECT_FALSE(invalid.contains({0, 0, 1}));
}

}  // namespace
}  // namespace rayaccel
