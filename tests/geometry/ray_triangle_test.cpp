// Unit tests of the watertight ray/triangle kernel (geometry/ray_triangle.h, Woop et al. 2013): barycentrics, both
// sides, the t_min < t <= t_max rule, no leaks through shared edges and vertices of grids and fans, and no hits on
// degenerate or NaN triangles.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "../conformance/test_scenes.h"
#include "rayaccel/geometry/ray_triangle.h"
#include "../float_specials.h"

namespace rayaccel {
namespace {

using conformance::Rng;

using test_values::kInf;
using test_values::kNaN;

using Triangle = std::array<Vec3, 3>;

/// Tests one triangle alone; the hit (or a miss record) comes back.
bool hit_triangle(const Ray& ray, const Triangle& tri, Hit* out = nullptr) {
  const PreparedRay r(ray);
  Hit hit = Hit::begin(r);
  const bool found = intersect_triangle(r, tri[0], tri[1], tri[2], 0, hit);
  if (out) *out = hit;
  return found;
}

TEST(RayTriangle, HitsCenterWithEmbreeBarycentrics) {
  const Vec3 v0{0, 0, 0}, v1{1, 0, 0}, v2{0, 1, 0};
  Ray ray{{0.25f, 0.5f, -1.0f}, 0.0f, {0, 0, 1}, 10.0f};
  PreparedRay pr(ray);
  Hit hit = Hit::begin(pr);
  ASSERT_TRUE(intersect_triangle(pr, v0, v1, v2, 7, hit));
  EXPECT_FLOAT_EQ(hit.t, 1.0f);
  EXPECT_EQ(hit.prim_id, 7u);
  EXPECT_FLOAT_EQ(hit.u, 0.25f);
  EXPECT_FLOAT_EQ(hit.v, 0.5f);
}

TEST(RayTriangle, BarycentricsReproduceTheHitPoint) {
  Rng rng(1);
  for (int i = 0; i < 2000; ++i) {
    const Triangle tri{rng.unit_vector(), rng.unit_vector() * 2.0f, rng.unit_vector() + Vec3{0.5f}};
    const float u = rng.uniform(0.01f, 0.98f), v = rng.uniform(0.01f, 0.99f - u);
    const Vec3 target = tri[0] * (1.0f - u - v) + tri[1] * u + tri[2] * v;
    const Vec3 origin = target + rng.unit_vector() * rng.uniform(0.5f, 5.0f);
    Hit hit;
    const Vec3 normal = cross(tri[1] - tri[0], tri[2] - tri[0]);
    const Vec3 d = target - origin;
    // Skip near edge-on views, where the target's barycentrics are ill-conditioned.
    if (std::fabs(dot(normalize(normal), normalize(d))) < 0.05f) continue;
    ASSERT_TRUE(hit_triangle(Ray{origin, 0.0f, d, kInf}, tri, &hit)) << i;
    EXPECT_NEAR(hit.t, 1.0f, 1e-4f);
    EXPECT_NEAR(hit.u, u, 1e-4f);
    EXPECT_NEAR(hit.v, v, 1e-4f);
  }
  // Exact at the vertices.
  const Triangle tri{Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}};
  Hit hit;
  ASSERT_TRUE(hit_triangle(Ray{{1, 0, -1}, 0.0f, {0, 0, 1}, kInf}, tri, &hit));
  EXPECT_EQ(hit.u, 1.0f);
  EXPECT_EQ(hit.v, 0.0f);
  ASSERT_TRUE(hit_triangle(Ray{{0, 1, -1}, 0.0f, {0, 0, 1}, kInf}, tri, &hit));
  EXPECT_EQ(hit.u, 0.0f);
  EXPECT_EQ(hit.v, 1.0f);
}

TEST(RayTriangle, HitsFromBothSides) {
  const Triangle tri{Vec3{0, 0, 2}, Vec3{1, 0, 2}, Vec3{0, 1, 2}};
  Hit front, back;
  ASSERT_TRUE(hit_triangle(Ray{{0.2f, 0.3f, 0.0f}, 0.0f, {0, 0, 1}, kInf}, tri, &front));
  ASSERT_TRUE(hit_triangle(Ray{{0.2f, 0.3f, 4.0f}, 0.0f, {0, 0, -1}, kInf}, tri, &back));
  EXPECT_EQ(front.t, 2.0f);
  EXPECT_EQ(back.t, 2.0f);
  EXPECT_FLOAT_EQ(front.u, back.u);
  EXPECT_FLOAT_EQ(front.v, back.v);
  EXPECT_FALSE(hit_triangle(Ray{{0.2f, 0.3f, 0.0f}, 0.0f, {0, 0, -1}, kInf}, tri)) << "behind the origin";
}

TEST(RayTriangle, TMaxIsInclusiveAndTMinExclusive) {
  const Triangle tri{Vec3{-1, -1, 2}, Vec3{3, -1, 2}, Vec3{-1, 3, 2}};
  const Vec3 o{0, 0, 0}, d{0, 0, 1};  // hits at t == 2 exactly
  const float below = std::nextafter(2.0f, 0.0f), above = std::nextafter(2.0f, kInf);
  EXPECT_TRUE(hit_triangle(Ray{o, 0.0f, d, 2.0f}, tri)) << "t == t_max counts";
  EXPECT_FALSE(hit_triangle(Ray{o, 0.0f, d, below}, tri));
  EXPECT_FALSE(hit_triangle(Ray{o, 2.0f, d, kInf}, tri)) << "t == t_min does not count";
  // t_min one ulp below the hit: within the bound on t's rounding error, so not counted (see ray_triangle.h);
  // t_min clear of it (by 1e-5 relative here) is.
  EXPECT_FALSE(hit_triangle(Ray{o, below, d, kInf}, tri)) << "a hit within t's error bound above t_min";
  EXPECT_TRUE(hit_triangle(Ray{o, 2.0f * (1.0f - 1e-5f), d, kInf}, tri));
  EXPECT_FALSE(hit_triangle(Ray{o, above, d, kInf}, tri));
  EXPECT_FALSE(hit_triangle(Ray{o, 2.0f, d, 2.0f}, tri)) << "t_min == t_max: the interval (t_min, t_max] is empty";
  EXPECT_FALSE(hit_triangle(Ray{o, 0.0f, d, 0.0f}, tri)) << "t_max = 0";
  EXPECT_TRUE(hit_triangle(Ray{{0, 0, 4}, -kInf, d, 0.0f}, tri)) << "behind the origin with t_min = -inf";
  // A closer hit already found shrinks the exclusive bound.
  const PreparedRay r(Ray{o, 0.0f, d, kInf});
  Hit hit = Hit::begin(r);
  hit.t = 2.0f;
  EXPECT_FALSE(intersect_triangle(r, tri[0], tri[1], tri[2], 0, hit)) << "equal t does not replace an earlier hit";
}

/// A ray leaving a large floor from a hair above it (one subnormal ulp, as render/workloads.h's offset gives an exact
/// point on y = 0) moves away from the plane: exactly, it never meets it. The computed t of such a grazing plane hit
/// is rounding noise of the size of the vertex coordinates times 2^-24 and can come out positive; the kernel must
/// not count it (box culling, exactly conservative, rules it out, so structures would disagree with brute force).
TEST(RayTriangle, RayLeavingAPlaneFromAHairAboveNeverHitsIt) {
  const Triangle floor{Vec3{-500.0f, 0.0f, -1000.0f}, Vec3{-500.0f, 0.0f, -500.0f}, Vec3{0.0f, 0.0f, -500.0f}};
  Rng rng(91);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    Ray ray;
    ray.origin = {-100.0f - 300.0f * rng.uniform(), 0x1p-149f, -600.0f - 300.0f * rng.uniform()};
    ray.direction = normalize(Vec3{rng.uniform() - 0.5f, 0.05f + rng.uniform(), rng.uniform() - 0.5f});
    Hit hit;
    if (hit_triangle(ray, floor, &hit)) {
      ++hits;
      if (hits < 4) ADD_FAILURE() << "hit at t = " << hit.t << " from y = 2^-149 moving up";
    }
  }
  EXPECT_EQ(hits, 0);
}

/// A ray parallel to a wall and a subnormal distance beyond its bottom edge: the edge function of that edge is a
/// tiny nonzero number, exactly zero in float, so the kernel decides it in double, and the conversion back to float
/// must keep its sign (a zero would count the ray as on the edge, a hit).
TEST(RayTriangle, SubnormalEdgeFunctionsKeepTheirSign) {
  // The bottom edge is short (0.25), so 2^-149 times the sheared edge coordinates rounds to the same float at both
  // ends and the float edge function cancels to zero.
  const Triangle wall{Vec3{0.0f, 1.0f, 0.0f}, Vec3{0.25f, 1.0f, 0.0f}, Vec3{0.0f, 1.0f, 5.0f}};
  Rng rng(92);
  int hits = 0;
  int hits_above = 0;
  for (int i = 0; i < 1000; ++i) {
    const Vec3 d{0.02f * (rng.uniform() - 0.5f), 0.5f + rng.uniform(), 0.0f};
    const float x = 0.03f + 0.19f * rng.uniform();
    // Below the edge z = 0: exactly a miss. Just above it: exactly a hit.
    hits += hit_triangle(Ray{Vec3{x, 0.25f, -0x1p-149f}, 0.0f, d, kInf}, wall) ? 1 : 0;
    hits_above += hit_triangle(Ray{Vec3{x, 0.25f, 0x1p-149f}, 0.0f, d, kInf}, wall) ? 1 : 0;
  }
  EXPECT_EQ(hits, 0) << "rays passing 2^-149 below the wall's edge";
  EXPECT_EQ(hits_above, 1000) << "rays passing 2^-149 above the wall's edge";
}

/// The bound on t's rounding error does not cost real hits: a ray from just below the plane (exactly at distance
/// 2^-149) going straight up hits it, and an ordinary hit still counts with t_min a little below it.
TEST(RayTriangle, ErrorBoundOnTKeepsExactSmallAndOrdinaryHits) {
  const Triangle floor{Vec3{-500.0f, 0.0f, -1000.0f}, Vec3{-500.0f, 0.0f, -500.0f}, Vec3{0.0f, 0.0f, -500.0f}};
  Ray up;
  up.origin = {-400.0f, -0x1p-149f, -600.0f};
  up.direction = {0.0f, 1.0f, 0.0f};
  Hit hit;
  ASSERT_TRUE(hit_triangle(up, floor, &hit));
  EXPECT_EQ(hit.t, 0x1p-149f);
  Ray down;
  down.origin = {-400.0f, 3.0f, -600.0f};
  down.direction = normalize(Vec3{0.1f, -1.0f, 0.2f});
  ASSERT_TRUE(hit_triangle(down, floor, &hit));
  down.t_min = hit.t * 0.999f;  // far below the hit compared with its error bound
  EXPECT_TRUE(hit_triangle(down, floor));
}

TEST(RayTriangle, HugeAndTinyCoordinates) {
  // Edge functions grow with the square of the coordinates and the scaled t with their cube: the test must still
  // find these hits (a float overflow of that product turns t into inf or NaN, a silent miss).
  for (float scale : {1e-18f, 1e-10f, 1.0f, 1e6f, 1e12f, 1e15f, 1e18f}) {
    const Triangle tri{Vec3{-1, -1, 5} * scale, Vec3{3, -1, 5} * scale, Vec3{-1, 3, 5} * scale};
    Hit hit;
    EXPECT_TRUE(hit_triangle(Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, kInf}, tri, &hit)) << "scale " << scale;
    EXPECT_FLOAT_EQ(hit.t, 5.0f * scale) << "scale " << scale;
    EXPECT_TRUE(hit_triangle(Ray{Vec3{0.5f, 0.5f, 0} * scale, 0.0f, {0.1f, -0.2f, 1}, kInf}, tri)) << "scale " << scale;
  }
}

TEST(RayTriangle, LongDirectionsKeepTheTOfRescaledTriangles) {
  // A triangle 1e36 across is scaled by a power of two into the safe range; a direction 1e28 long then made each
  // vertex's depth times 1 / d[kz] underflow (2^-54 * 2^-93) before the scale was undone, and t came out near 0.
  const Triangle wide{Vec3{-1e36f, -1e36f, 1e20f}, Vec3{3e36f, -1e36f, 1e20f}, Vec3{-1e36f, 3e36f, 1e20f}};
  Hit hit;
  ASSERT_TRUE(hit_triangle(Ray{{0, 0, 0}, 0.0f, {0, 0, 1e28f}, kInf}, wide, &hit));
  EXPECT_NEAR(hit.t, 1e-8f, 1e-8f * 1e-5f);
  // The fuzz input that found it (tests/fuzz/corpus/fuzz_differential/long-direction-rescaled-t): the exact t is 1
  // (rational arithmetic on these floats), which float reported as 0, inside a range that ends at 0.0027.
  const Triangle far{Vec3{0x1.8p-2f, -0x1.4f126ep+38f, -0x1.16ce48p-65f}, Vec3{0x1.40c92cp+87f, -0x1.2p+0f, 0x1.8p+0f},
                     Vec3{-0x1.67db44p+47f, -0x1.5p+1f, 0x1.2ced32p+127f}};
  const Vec3 origin{0x1.8p+2f, -0x1.8b4b0ap+93f, -0x1.b7e83ep-90f};
  const Vec3 direction{0x1.40c92cp+86f, 0x1.8b4b0ap+93f, 0x1.8p-1f};
  ASSERT_TRUE(hit_triangle(Ray{origin, -4.0f, direction, kInf}, far, &hit));
  EXPECT_NEAR(hit.t, 1.0f, 1e-5f);
  EXPECT_FALSE(hit_triangle(Ray{origin, -4.0f, direction, 0x1.670bdep-9f}, far));
}

TEST(RayTriangle, HugeTrianglesWithTinyDepthsKeepTheirT) {
  // A triangle 2^100 wide across the ray and flat along it, hit at its corner: rescaled by 2^-100, its depths
  // (1.1 * 2^-100) times its edge functions (2^-40) fell below float's normal range, so t lost most of its bits.
  const float z = 1.1f;
  const Triangle flat{Vec3{0, 0, z}, Vec3{0x1p100f, 0, z}, Vec3{0, 0x1p60f, z}};
  Hit hit;
  ASSERT_TRUE(hit_triangle(Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, kInf}, flat, &hit));
  EXPECT_NEAR(hit.t, z, 12 * z * 0x1p-24f) << "a flat triangle's t is within 12 ulps of its depth";
  // The fuzz input that found it (tests/fuzz/corpus/fuzz_differential/huge-triangle-tiny-depth-t): the ray is aimed
  // exactly at the first vertex (origin + direction), so t = 1; float said 0.9066.
  const Triangle wide{Vec3{0x1.314758p+10f, 0x1.1p+2f, 0x1.08p+3f}, Vec3{0x1.4383dap+85f, 0x1.91a0ccp+18f, 0x1.8p-2f},
                      Vec3{0x1.8966p+43f, 0x1.508128p+122f, -0x1.898faap-29f}};
  ASSERT_TRUE(hit_triangle(Ray{{0, -0.0f, 0x1p+11f}, 0.0f, {0x1.314758p+10f, 0x1.1p+2f, -0x1.fdfp+10f}, kInf}, wide,
                           &hit));
  EXPECT_NEAR(hit.t, 1.0f, 1e-5f);
  // Its two siblings (corpus huge-triangle-tiny-depth-missed, ...-negative-interval): interior hits that float
  // dropped, at exact t = 0.00035392391 and -5.09810251e-12 (rational arithmetic on these floats).
  const Triangle tall{Vec3{0x1.21206cp-36f, -0x1.ed3da8p+83f, -0x1.a83beep-76f}, Vec3{0x1.b8p+2f, -0x1.78e2dp-18f,
                      -0x1p+2f}, Vec3{-0x1.7p+1f, 0x1.196d78p+88f, -0x1.31acc6p-89f}};
  ASSERT_TRUE(hit_triangle(Ray{{0x1.b7eedep-6f, 0x1.ep+0f, -0x1.5p+1f}, 0.0f, {0x1.876fbcp+13f, 0x1.6p+0f, 0x1p-1f},
                               kInf}, tall, &hit));
  EXPECT_NEAR(hit.t, 0.00035392391f, 0.00035392391f * 1e-5f);
  const Triangle long_one{Vec3{0x1.8p-2f, 0x1.7p+1f, -0x1.517e78p+58f}, Vec3{0x1.88p+2f, 0x1.fp+2f, 0x1.f8p+2f},
                          Vec3{0x1.16c2p-133f, -0x1.dff4b4p+111f, 0x1.c6a182p+56f}};
  ASSERT_TRUE(hit_triangle(Ray{{0x1.68p+2f, 0x1.8p+2f, 0x1.a8p+2f}, -0x1.8d31cap-5f,
                               {-0x1.6d5c48p+36f, 0x1.8p+0f, -0x1.d8p+1f}, -0x1.f9415p-45f}, long_one, &hit));
  EXPECT_NEAR(hit.t, -5.09810251e-12f, 5.09810251e-12f * 1e-5f);
}

TEST(RayTriangle, EdgesNearTheRayKeepTValuesPreciseEnoughForTMin) {
  // Fuzz corpus exact-edge-value-imprecise: two edge functions of this triangle 3e26 long are within float's error
  // of zero, so they were recomputed in double, whose static bound then decided their signs but left their values
  // wrong by up to 100 times their size; t's bound grew to 0.995 and the hit at exact t = 0.00285160179 (rational
  // arithmetic on these floats; u = 0.0014258009, v = 0.997148398) was dropped against t_min = -0.5.
  const Triangle long_one{Vec3{-0x1.7p+1f, 0x1.189486p+88f, 0x1.1cp+3f}, Vec3{0x1.08p+3f, -0x1.0733ap+42f, 0x1.3e7cp+55f},
                          Vec3{0x1.d8p+2f, 0x1.ep+0f, -0x1.5p+1f}};
  Hit hit;
  ASSERT_TRUE(hit_triangle(Ray{{0x1.d8p+2f, 0x1.d8p+2f, 0x1.d8p+2f}, -0.5f,
                               {-0x1.2cp+2f, 0x1.189486p+87f, 0x1.3e7cp+54f}, 0x1.d8p+2f}, long_one, &hit));
  EXPECT_NEAR(hit.t, 0.00285160179f, 0.00285160179f * 1e-5f);
  EXPECT_NEAR(hit.u, 0.0014258009f, 1e-6f);
  EXPECT_NEAR(hit.v, 0.997148398f, 1e-6f);
}

/// Vertices of an n x n grid of unit quads on a tilted plane (each vertex rounded on its own, so the grid is only
/// nearly planar); two triangles per quad, vertices shared.
struct Grid {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::vector<Vec3> interior_targets;  ///< interior vertices and midpoints of interior edges
};

Grid tilted_grid(int n) {
  Grid g;
  auto at = [n](int i, int j) { return i * (n + 1) + j; };
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const float x = static_cast<float>(i), y = static_cast<float>(j);
      g.vertices.push_back({x, y, 0.3f * x - 0.7f * y});
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      g.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      g.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  for (int i = 1; i < n; ++i) {
    for (int j = 1; j < n; ++j) {
      const Vec3& v = g.vertices[static_cast<std::size_t>(at(i, j))];
      g.interior_targets.push_back(v);
      for (int k : {at(i + 1, j), at(i, j + 1), at(i + 1, j + 1), at(i - 1, j), at(i, j - 1), at(i - 1, j - 1)}) {
        g.interior_targets.push_back((v + g.vertices[static_cast<std::size_t>(k)]) * 0.5f);
      }
    }
  }
  return g;
}

/// Number of grid triangles the ray hits, each tested on its own.
int hit_count(const Grid& g, const Ray& ray) {
  int count = 0;
  for (const auto& t : g.triangles) {
    count += hit_triangle(ray, {g.vertices[static_cast<std::size_t>(t[0])], g.vertices[static_cast<std::size_t>(t[1])],
                                g.vertices[static_cast<std::size_t>(t[2])]})
                 ? 1
                 : 0;
  }
  return count;
}

TEST(RayTriangle, NoLeaksThroughSharedEdgesAndVerticesOfAGrid) {
  const Grid g = tilted_grid(4);
  Rng rng(2);
  for (const Vec3& target : g.interior_targets) {
    for (int k = 0; k < 40; ++k) {
      const Vec3 o = target + rng.unit_vector() * rng.uniform(0.5f, 20.0f);
      const Vec3 d = target - o;
      // A ray grazing the plane sees edges as silhouettes, where the rounded target may lie just off both triangles.
      if (std::fabs(dot(normalize(d), normalize(Vec3{-0.3f, 0.7f, 1.0f}))) < 0.1f) continue;
      ASSERT_GE(hit_count(g, Ray{o, 0.0f, d, kInf}), 1) << "leak at (" << target.x << ", " << target.y << ", "
                                                        << target.z << ") from (" << o.x << ", " << o.y << ", " << o.z
                                                        << ")";
    }
  }
}

TEST(RayTriangle, AxisRaysThroughGridEdgesAndVerticesNeverLeak) {
  // A flat grid in z = 1 hit by rays along -z/+z with +-0 in x and y, exactly at vertices and edge points.
  const int n = 4;
  Grid g;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) g.vertices.push_back({static_cast<float>(i), static_cast<float>(j), 1.0f});
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const int a = i * (n + 1) + j;
      g.triangles.push_back({a, a + n + 1, a + n + 2});
      g.triangles.push_back({a, a + n + 2, a + 1});
    }
  }
  for (float x = 0.5f; x <= n - 0.5f; x += 0.5f) {
    for (float y = 0.5f; y <= n - 0.5f; y += 0.5f) {
      for (int bits = 0; bits < 8; ++bits) {
        const Vec3 d{(bits & 1) ? -0.0f : 0.0f, (bits & 2) ? -0.0f : 0.0f, (bits & 4) ? -1.0f : 1.0f};
        const Ray ray{{x, y, (bits & 4) ? 3.0f : -1.0f}, 0.0f, d, kInf};
        EXPECT_GE(hit_count(g, ray), 1) << "leak at (" << x << ", " << y << ") bits " << bits;
      }
    }
  }
}

TEST(RayTriangle, NoLeaksThroughTheCenterOfAFan) {
  Rng rng(3);
  for (int fan = 0; fan < 20; ++fan) {
    const Vec3 center = rng.in_box(AABB(Vec3{-1.0f}, Vec3{1.0f}));
    const int k = 3 + static_cast<int>(rng.below(8));
    Grid g;
    g.vertices.push_back(center);
    for (int i = 0; i < k; ++i) {
      const float phi = 2.0f * 3.14159265f * (static_cast<float>(i) + rng.uniform(0.0f, 0.5f)) / static_cast<float>(k);
      g.vertices.push_back(center + Vec3{std::cos(phi), std::sin(phi), rng.uniform(-0.2f, 0.2f)});
    }
    for (int i = 0; i < k; ++i) g.triangles.push_back({0, 1 + i, 1 + (i + 1) % k});
    for (int r = 0; r < 100; ++r) {
      Vec3 d = rng.unit_vector();
      if (std::fabs(d.z) < 0.6f) continue;  // keep the fan seen face-on enough to cover its center
      const Vec3 o = center - d * rng.uniform(0.5f, 10.0f);
      EXPECT_GE(hit_count(g, Ray{o, 0.0f, center - o, kInf}), 1) << "fan " << fan << " ray " << r;
    }
  }
}

TEST(RayTriangle, TrianglesWithRepeatedVerticesAreNeverHit) {
  // Repeated vertices make an edge function exactly zero and the determinant exactly zero in any ray's frame.
  Rng rng(4);
  for (int i = 0; i < 500; ++i) {
    const Vec3 a = rng.unit_vector(), b = rng.unit_vector();
    for (const Triangle& tri : {Triangle{a, a, a}, Triangle{a, b, b}, Triangle{a, b, a}, Triangle{b, a, a}}) {
      for (const Vec3& target : {tri[0], tri[1], (tri[0] + tri[1]) * 0.5f, (tri[1] + tri[2]) * 0.5f}) {
        const Vec3 o = target + rng.unit_vector() * 3.0f;
        EXPECT_FALSE(hit_triangle(Ray{o, -kInf, target - o, kInf}, tri));
      }
    }
  }
}

TEST(RayTriangle, RaysInTheTrianglesPlaneMiss) {
  const Triangle tri{Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}};
  EXPECT_FALSE(hit_triangle(Ray{{-1.0f, 0.25f, 0.0f}, 0.0f, {1.0f, 0.0f, 0.0f}, kInf}, tri));
  EXPECT_FALSE(hit_triangle(Ray{{-1.0f, -1.0f, 0.0f}, 0.0f, {1.0f, 1.0f, -0.0f}, kInf}, tri));
}

TEST(RayTriangle, NaNVerticesAreNeverHit) {
  const Vec3 good0{-1, -1, 1}, good1{3, -1, 1};
  for (float bad : {kNaN, -kNaN}) {
    for (int axis = 0; axis < 3; ++axis) {
      Vec3 v{-1, 3, 1};
      v[axis] = bad;
      for (const Ray& ray : {Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, kInf}, Ray{{0.1f, 0.2f, 0}, -kInf, {0.1f, 0.1f, 1}, kInf},
                             Ray{{0, 0, 5}, 0.0f, {0, 0, -1}, kInf}}) {
        EXPECT_FALSE(hit_triangle(ray, {good0, good1, v})) << bad << " axis " << axis;
        EXPECT_FALSE(hit_triangle(ray, {v, good0, good1})) << bad << " axis " << axis;
      }
    }
  }
}

TEST(RayTriangle, VoidRaysNeverHit) {
  const Triangle tri{Vec3{-1, -1, 1}, Vec3{3, -1, 1}, Vec3{-1, 3, 1}};
  for (const Ray& ray : {Ray{{kNaN, 0, 0}, 0.0f, {0, 0, 1}, kInf}, Ray{{0, 0, 0}, 0.0f, {0, kNaN, 1}, kInf},
                         Ray{{0, 0, 0}, 0.0f, {0, 0, 0}, kInf}, Ray{{0, 0, 0}, 0.0f, {-0.0f, -0.0f, -0.0f}, kInf},
                         Ray{{0, 0, 0}, kNaN, {0, 0, 1}, kInf}, Ray{{0, 0, 0}, 3.0f, {0, 0, 1}, 2.0f}}) {
    EXPECT_FALSE(hit_triangle(ray, tri));
  }
}

}  // namespace
}  // namespace rayaccel
