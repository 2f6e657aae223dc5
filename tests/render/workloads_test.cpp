// Tests of the ray workloads: the packet tile order, determinism, thread-count independence, cosine-weighted
// hemisphere sampling, and secondary-ray origins that never re-hit the surface they leave.
#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "rayaccel/accel/brute_force.h"
#include "rayaccel/core/error.h"
#include "rayaccel/render/sampling.h"
#include "rayaccel/render/workloads.h"

namespace rayaccel {
namespace {

/// A square of two triangles: corner c, edges a and b (normal along cross(a, b)).
Scene quad_scene(const Vec3& c, const Vec3& a, const Vec3& b) {
  TriangleMesh mesh;
  mesh.vertices = {c, c + a, c + a + b, c + b};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return Scene::from_mesh(std::move(mesh), "quad");
}

struct Traced {
  std::vector<Ray> rays;
  std::vector<Hit> hits;
};

Traced trace_primary(const Scene& scene, const Camera& cam, int size) {
  BruteForce bf;
  bf.build(scene);
  Traced t;
  t.rays = primary_rays(cam, size, size);
  t.hits.resize(t.rays.size());
  bf.intersect(t.rays, t.hits);
  return t;
}

Camera looking_at(const Vec3& eye, const Vec3& at) {
  Camera cam;
  cam.eye = eye;
  cam.at = at;
  cam.fov_degrees = 30.0f;
  return cam;
}

bool same_rays(const std::vector<Ray>& a, const std::vector<Ray>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].origin != b[i].origin || a[i].direction != b[i].direction || a[i].t_min != b[i].t_min ||
        a[i].t_max != b[i].t_max) {
      return false;
    }
  }
  return true;
}

TEST(Workloads, PrimaryRaysAreRowMajorFromTopLeft) {
  const Camera cam = looking_at({0, 0, 5}, {0, 0, 0});
  const std::vector<Ray> rays = primary_rays(cam, 7, 5);
  ASSERT_EQ(rays.size(), 35u);
  for (int y = 0; y < 5; ++y) {
    for (int x = 0; x < 7; ++x) {
      const Ray expected = cam.primary_ray(x, y, 7, 5);
      EXPECT_EQ(rays[y * 7 + x].direction, expected.direction);
    }
  }
  EXPECT_THROW(primary_rays(cam, 0, 5), Error);
}

TEST(Workloads, PacketTilesAreFourByTwoPixelsInRowMajorOrder) {
  // 8 x 4: four whole tiles, no remainder.
  const std::vector<std::size_t> even = packet_tile_order(8, 4);
  const std::vector<std::size_t> expected = {0,  1,  2,  3,  8,  9,  10, 11,   // tile (0, 0)
                                             4,  5,  6,  7,  12, 13, 14, 15,   // tile (1, 0)
                                             16, 17, 18, 19, 24, 25, 26, 27,   // tile (0, 1)
                                             20, 21, 22, 23, 28, 29, 30, 31};  // tile (1, 1)
  EXPECT_EQ(even, expected);
  // 6 x 3: one whole tile, then the right strip of the tiled rows and the odd last row, row-major.
  const std::vector<std::size_t> odd = packet_tile_order(6, 3);
  const std::vector<std::size_t> expected_odd = {0, 1, 2, 3, 6, 7, 8, 9, 4, 5, 10, 11, 12, 13, 14, 15, 16, 17};
  EXPECT_EQ(odd, expected_odd);
  // Narrower or shorter than a tile: row-major throughout.
  const std::vector<std::size_t> thin = packet_tile_order(3, 2);
  EXPECT_EQ(thin, (std::vector<std::size_t>{0, 1, 2, 3, 4, 5}));
  // Every pixel once, for sizes with every remainder.
  for (int w = 1; w <= 9; ++w) {
    for (int h = 1; h <= 5; ++h) {
      std::vector<std::size_t> order = packet_tile_order(w, h);
      ASSERT_EQ(order.size(), static_cast<std::size_t>(w * h));
      std::sort(order.begin(), order.end());
      for (std::size_t i = 0; i < order.size(); ++i) EXPECT_EQ(order[i], i) << w << "x" << h;
    }
  }
  EXPECT_THROW(packet_tile_order(0, 4), Error);
  EXPECT_THROW(packet_tile_order(4, -1), Error);
}

TEST(Workloads, DeterministicAndIndependentOfThreadCount) {
  const Scene scene = quad_scene({-1, -1, 0}, {2, 0, 0}, {0, 2, 0});
  const Traced t = trace_primary(scene, looking_at({0.3f, 0.2f, 4}, {0, 0, 0}), 48);
  std::vector<Ray> one_thread, one_thread_shadow;
  tbb::task_arena single(1);
  single.execute([&] {
    one_thread = diffuse_rays(scene, t.rays, t.hits, 42);
    one_thread_shadow = shadow_rays(scene, t.rays, t.hits, 0.5f, 42);
  });
  const std::vector<Ray> many = diffuse_rays(scene, t.rays, t.hits, 42);
  const std::vector<Ray> again = diffuse_rays(scene, t.rays, t.hits, 42);
  const std::vector<Ray> other_seed = diffuse_rays(scene, t.rays, t.hits, 43);
  ASSERT_GT(many.size(), 100u);
  EXPECT_TRUE(same_rays(one_thread, many));
  EXPECT_TRUE(same_rays(many, again));
  EXPECT_FALSE(same_rays(many, other_seed));
  EXPECT_TRUE(same_rays(one_thread_shadow, shadow_rays(scene, t.rays, t.hits, 0.5f, 42)));
}

TEST(Workloads, OneRayPerHitInHitOrder) {
  const Scene scene = quad_scene({-1, -1, 0}, {2, 0, 0}, {0, 2, 0});
  const Traced t = trace_primary(scene, looking_at({0, 0, 5}, {0, 0, 0}), 32);
  std::size_t hit_count = 0;
  for (const Hit& h : t.hits) hit_count += h.found() ? 1 : 0;
  ASSERT_GT(hit_count, 0u);
  ASSERT_LT(hit_count, t.hits.size());  // the camera sees past the quad's edges too
  const std::vector<Ray> shadow = shadow_rays(scene, t.rays, t.hits, 0.25f, 1);
  ASSERT_EQ(shadow.size(), hit_count);
  std::size_t k = 0;
  for (std::size_t i = 0; i < t.hits.size(); ++i) {
    if (!t.hits[i].found()) continue;
    const Vec3 p = t.rays[i].origin + t.rays[i].direction * t.hits[i].t;
    EXPECT_LT(length(shadow[k].origin - p), 1e-5f);
    EXPECT_EQ(shadow[k].t_max, 0.25f);
    EXPECT_EQ(shadow[k].t_min, 0.0f);
    EXPECT_NEAR(length(shadow[k].direction), 1.0f, 1e-6f);
    ++k;
  }
  EXPECT_THROW(shadow_rays(scene, t.rays, t.hits, -1.0f, 1), Error);
  EXPECT_THROW(diffuse_rays(scene, t.rays, std::span<const Hit>(t.hits).first(3), 1), Error);
}

TEST(Workloads, DiffuseDirectionsStayOnTheIncomingSide) {
  const Scene scene = quad_scene({-1, -1, 0}, {2, 0, 0}, {0, 2, 0});  // normal +z
  for (const float side : {1.0f, -1.0f}) {
    const Traced t = trace_primary(scene, looking_at({0.2f, -0.1f, 3.0f * side}, {0, 0, 0}), 32);
    const std::vector<Ray> bounced = diffuse_rays(scene, t.rays, t.hits, 5);
    ASSERT_GT(bounced.size(), 100u);
    for (const Ray& r : bounced) {
      EXPECT_GT(r.direction.z * side, 0.0f);
      EXPECT_GT(r.origin.z * side, 0.0f);  // lifted off the plane z = 0 toward the camera
    }
  }
}

// With density cos(theta)/pi, cos(theta) has mean 2/3 and standard deviation sqrt(1/2 - 4/9) = 0.2357, and
// cos^2(theta) is uniform on [0, 1] (mean 1/2, sd 0.2887). With n samples the sample means lie within 5 standard
// errors of the expectation except with probability below 1e-6; the seed is fixed, so the test is repeatable.
TEST(Workloads, DiffuseDirectionsAreCosineWeighted) {
  const Scene scene = quad_scene({-4, -4, 0}, {8, 0, 0}, {0, 8, 0});
  const Traced t = trace_primary(scene, looking_at({0.0f, 0.0f, 2.0f}, {0, 0, 0}), 128);
  const std::vector<Ray> bounced = diffuse_rays(scene, t.rays, t.hits, 2024);
  const double n = static_cast<double>(bounced.size());
  ASSERT_EQ(bounced.size(), 128u * 128u);
  double sum_cos = 0.0, sum_cos2 = 0.0, sum_x = 0.0, sum_y = 0.0;
  for (const Ray& r : bounced) {
    const double c = r.direction.z;
    sum_cos += c;
    sum_cos2 += c * c;
    sum_x += r.direction.x;
    sum_y += r.direction.y;
  }
  const double five_se = 5.0 / std::sqrt(n);
  EXPECT_NEAR(sum_cos / n, 2.0 / 3.0, 0.2357 * five_se);
  EXPECT_NEAR(sum_cos2 / n, 0.5, 0.2887 * five_se);
  // Tangential components: mean 0, variance (1 - E[cos^2]) / 2 = 1/4.
  EXPECT_NEAR(sum_x / n, 0.0, 0.5 * five_se);
  EXPECT_NEAR(sum_y / n, 0.0, 0.5 * five_se);
}

/// Traces every ray against the scene with brute force; returns how many hit anything.
std::size_t count_hits(const Scene& scene, const std::vector<Ray>& rays) {
  BruteForce bf;
  bf.build(scene);
  std::vector<Hit> hits(rays.size());
  bf.intersect(rays, hits);
  std::size_t n = 0;
  for (const Hit& h : hits) n += h.found() ? 1 : 0;
  return n;
}

TEST(Workloads, DiffuseRaysNeverReHitAFlatSurface) {
  // A tilted plane far from the origin, seen from far away: the hit point's rounding error is largest here.
  const Vec3 corner{1000.0f, -500.0f, 300.0f};
  const Scene scene = quad_scene(corner, {37.0f, 11.0f, -5.0f}, {-3.0f, 21.0f, 29.0f});
  const Vec3 center = corner + Vec3{17.0f, 16.0f, 12.0f};
  const Vec3 normal = normalize(cross(Vec3{37.0f, 11.0f, -5.0f}, Vec3{-3.0f, 21.0f, 29.0f}));
  for (const float side : {1.0f, -1.0f}) {
    const Traced t = trace_primary(scene, looking_at(center + normal * (80.0f * side), center), 96);
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
      const std::vector<Ray> bounced = diffuse_rays(scene, t.rays, t.hits, seed);
      ASSERT_GT(bounced.size(), 2000u);
      EXPECT_EQ(count_hits(scene, bounced), 0u) << "side " << side << " seed " << seed;
    }
  }
}

TEST(Workloads, DiffuseRaysNeverReHitAConvexSphere) {
  const Scene scene = Scene::from_spheres({{{250.0f, -120.0f, 75.0f}, 3.0f}});
  const Traced t = trace_primary(scene, looking_at({250.0f, -120.0f, 95.0f}, {250.0f, -120.0f, 75.0f}), 96);
  const std::vector<Ray> bounced = diffuse_rays(scene, t.rays, t.hits, 9);
  ASSERT_GT(bounced.size(), 1000u);
  EXPECT_EQ(count_hits(scene, bounced), 0u);
}

TEST(Workloads, FixedOffsetMovesOriginsThatFarAlongTheNormal) {
  // The plane z = 0 seen from above: the normal facing the camera is +z, so origins sit at z = 0.01 exactly.
  const Scene scene = quad_scene({-1.0f, -1.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f});
  const Traced t = trace_primary(scene, looking_at({0.0f, 0.0f, 3.0f}, {0.0f, 0.0f, 0.0f}), 32);
  const std::vector<Ray> tight = shadow_rays(scene, t.rays, t.hits, 0.5f, 7);
  const std::vector<Ray> fixed = shadow_rays(scene, t.rays, t.hits, 0.5f, 7, OriginOffset{0.01f});
  ASSERT_EQ(fixed.size(), tight.size());
  ASSERT_GT(fixed.size(), 100u);
  for (std::size_t i = 0; i < fixed.size(); ++i) {
    EXPECT_FLOAT_EQ(fixed[i].origin.z, 0.01f) << i;
    EXPECT_LT(tight[i].origin.z, 1e-5f) << i;  // pbrt's offset is a few ulps here
    EXPECT_EQ(fixed[i].direction, tight[i].direction) << i;
    EXPECT_EQ(fixed[i].t_max, 0.5f);
  }
  EXPECT_THROW(diffuse_rays(scene, t.rays, t.hits, 7, OriginOffset{-1.0f}), Error);
  EXPECT_THROW(diffuse_rays(scene, t.rays, t.hits, 7, OriginOffset{std::nanf("")}), Error);
}

TEST(Workloads, LightRaysEndJustBeforeTheLight) {
  // A floor at z = 0 and, between part of it and the light, a small occluder at z = 1.
  TriangleMesh mesh;
  mesh.vertices = {{-2, -2, 0}, {2, -2, 0}, {2, 2, 0}, {-2, 2, 0}, {-0.5f, -0.5f, 1}, {0.5f, -0.5f, 1},
                   {0.5f, 0.5f, 1}, {-0.5f, 0.5f, 1}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  const Scene scene = Scene::from_mesh(std::move(mesh), "floor");
  const Traced t = trace_primary(scene, looking_at({0.0f, -6.0f, 6.0f}, {0.0f, 0.0f, 0.0f}), 48);
  const Vec3 light{0.0f, 0.0f, 3.0f};
  const std::vector<Ray> rays = light_rays(scene, t.rays, t.hits, light);
  std::size_t hits = 0;
  for (const Hit& h : t.hits) hits += h.found() ? 1 : 0;
  ASSERT_EQ(rays.size(), hits);
  BruteForce bf;
  bf.build(scene);
  std::size_t shadowed = 0, lit = 0;
  for (const Ray& r : rays) {
    EXPECT_EQ(r.t_min, 0.0f);
    EXPECT_LT(r.t_max, 1.0f);
    EXPECT_LT(length(r.origin + r.direction - light), 1e-5f);  // the ray ends at the light
    const bool occluded = bf.occluded(r);
    // The occluder's shadow on the floor, seen from a light at height 3: |x|, |y| <= 0.5 * 3 / (3 - 1) = 0.75.
    const bool in_shadow = r.origin.z < 0.5f && std::abs(r.origin.x) < 0.75f && std::abs(r.origin.y) < 0.75f;
    const bool near_edge = r.origin.z < 0.5f && (std::abs(std::abs(r.origin.x) - 0.75f) < 0.02f ||
                                                 std::abs(std::abs(r.origin.y) - 0.75f) < 0.02f);
    if (!near_edge) {
      EXPECT_EQ(occluded, in_shadow) << r.origin.x << " " << r.origin.y << " " << r.origin.z;
    }
    (occluded ? shadowed : lit) += 1;
  }
  EXPECT_GT(shadowed, 10u);
  EXPECT_GT(lit, 10u);
  EXPECT_THROW(light_rays(scene, t.rays, t.hits, Vec3{std::nanf(""), 0.0f, 0.0f}), Error);
}

TEST(Sampling, UniformFloatsAreInRangeAndDiffer) {
  double sum = 0.0;
  for (std::uint64_t i = 0; i < 10000; ++i) {
    const float u = uniform_float(7, i, 0);
    ASSERT_GE(u, 0.0f);
    ASSERT_LT(u, 1.0f);
    sum += u;
  }
  // Mean of 10^4 uniforms: sd 0.2887 / 100; allow 5 standard errors.
  EXPECT_NEAR(sum / 10000.0, 0.5, 5.0 * 0.2887 / 100.0);
  EXPECT_NE(uniform_float(7, 3, 0), uniform_float(7, 3, 1));
  EXPECT_NE(uniform_float(7, 3, 0), uniform_float(8, 3, 0));
  EXPECT_EQ(uniform_float(7, 3, 0), uniform_float(7, 3, 0));
}

TEST(Sampling, OrthonormalBasisIncludingPoles) {
  for (const Vec3& n : {Vec3{0, 0, 1}, Vec3{0, 0, -1}, Vec3{1, 0, 0}, normalize(Vec3{0.3f, -0.7f, 0.2f}),
                        normalize(Vec3{1e-8f, 0.0f, -1.0f})}) {
    Vec3 t, b;
    orthonormal_basis(n, t, b);
    EXPECT_NEAR(length(t), 1.0f, 1e-6f);
    EXPECT_NEAR(length(b), 1.0f, 1e-6f);
    EXPECT_NEAR(dot(t, n), 0.0f, 1e-6f);
    EXPECT_NEAR(dot(b, n), 0.0f, 1e-6f);
    EXPECT_NEAR(dot(t, b), 0.0f, 1e-6f);
    EXPECT_GT(dot(cross(t, b), n), 0.999f);
  }
}

}  // namespace
}  // namespace rayaccel
