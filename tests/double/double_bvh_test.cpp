// The BVH in double (double/double_bvh.h) against brute force in double, for every builder, on random and
// adversarial rays over a sphere and a random soup placed near 1e7; rays that graze a box along an edge, which only
// the outward rounding of the box test keeps; batch forms against single rays; the spec parser's errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>

#include "../error_message.h"
#include "double_test_rays.h"
#include "rayaccel/double/double_accelerator.h"
#include "rayaccel/double/double_bvh.h"
#include "rayaccel/geometry/ray_triangle_d.h"
#include "rayaccel/scene/builtin_scenes.h"

namespace rayaccel {
namespace {

TriangleMeshD far_mesh(const char* name, std::map<std::string, std::string> params, double scale) {
  TriangleMesh mesh = make_builtin_scene(name, params).mesh();
  for (Vec3& v : mesh.vertices) v = v * float(scale);
  return to_double_mesh(mesh, DVec3{1.0e7, -1.3e7, 0.7e7});
}

/// The closest hits agree when they name the same triangle, or the same t within the ties the cull bound allows.
void expect_same_closest(const HitD& a, const HitD& b, std::size_t i) {
  ASSERT_EQ(a.found(), b.found()) << "ray " << i;
  if (!a.found() || a.prim_id == b.prim_id) {
    if (a.found()) {
      EXPECT_EQ(a.t, b.t) << "ray " << i;
    }
    return;
  }
  EXPECT_NEAR(a.t, b.t, std::fabs(a.t) * 1e-9) << "ray " << i << ": triangles " << a.prim_id << " and " << b.prim_id;
}

class DoubleBvhBuilders : public ::testing::TestWithParam<std::string> {};

TEST_P(DoubleBvhBuilders, MatchesBruteForceOnRandomAndAdversarialRays) {
  for (const auto& [name, params, scale] :
       {std::tuple<const char*, std::map<std::string, std::string>, double>{"sphere", {{"level", "3"}}, 10.0},
        {"soup", {{"count", "2000"}}, 5.0},
        {"sphere", {{"level", "2"}}, 0.05}}) {  // 5 cm across: far below float's ulp at 1e7
    const DoubleScene scene(far_mesh(name, params, scale));
    auto brute = make_double_accelerator("brute_force");
    auto bvh = make_double_accelerator("bvh:builder=" + GetParam());
    brute->build(scene);
    bvh->build(scene);
    EXPECT_TRUE(bvh->validate().empty()) << bvh->validate().front();
    std::vector<RayD> rays = testing::mixed_rays(scene.mesh(), 1500, scale, 21);
    const auto aimed = testing::aimed_rays(scene.mesh(), 600, scale * 3.0, 22);
    rays.insert(rays.end(), aimed.begin(), aimed.end());
    int found = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const HitD expected = brute->intersect(rays[i]);
      expect_same_closest(bvh->intersect(rays[i]), expected, i);
      EXPECT_EQ(bvh->occluded(rays[i]), expected.found()) << "ray " << i;
      found += expected.found() ? 1 : 0;
    }
    EXPECT_GT(found, 500) << name;  // the rays do reach the geometry
  }
}

INSTANTIATE_TEST_SUITE_P(All, DoubleBvhBuilders, ::testing::Values("binned", "sweep", "lbvh", "ploc", "sbvh"));

TEST(DoubleBvh, BoxesKeepFloatResolutionFarFromTheOrigin) {
  // A 10 cm sphere near 1e7: boxes rounded to float at 1e7 would be a metre wide (the ulp there); relative to the
  // anchor, the root box is as wide as the sphere and leaves are far smaller.
  const DoubleScene scene(far_mesh("sphere", {{"level", "3"}}, 0.05));
  DoubleBvh bvh;
  bvh.build(scene);
  ASSERT_TRUE(bvh.validate().empty()) << bvh.validate().front();
  const auto& nodes = bvh.tree().nodes();
  EXPECT_LT(nodes[0].volume.box.extent().x, 0.11f);
  double widest_leaf = 0.0;
  for (const auto& node : nodes) {
    if (node.is_leaf()) widest_leaf = std::max(widest_leaf, double(max_component(node.volume.box.extent())));
  }
  EXPECT_LT(widest_leaf, 0.05);
  EXPECT_GT(scene.triangle_box(0).extent().x, 0.9f);  // the absolute box at 1e7: float's metre grid
}

TEST(DoubleBvh, RaysGrazingABoxEdgeAtATriangleVertexStillHitIt) {
  // Two triangles near 1e7, mirror images through O, so the anchor (the centre of the scene's bounds) is O and every
  // ray starts at O: its origin in the box frame is exactly 0, so the face planes get no slack and only the outward
  // push of the slab distances (kSlabWidenUpD/DownD in ray_box_d.h) keeps the test conservative. Each ray passes
  // exactly through vertex v0 of the first triangle at t = k, entering its box's x slab as it leaves the y slab
  // (v0 lies on the box's edge x = lo.x, y = lo.y, exactly: integers near 1e7 are floats), so it touches that box at
  // one point: in exact arithmetic the slab intervals meet at t = k. Rounded, k * a * fl(1/a) and k * b * fl(1/b)
  // straddle k for some a and b, and without the push the box is missed although brute force hits the vertex.
  const DVec3 o{1.0e7, 1.0e7, 1.0e7};
  int plain_misses = 0;
  for (double k : {1.0, 3.0, 1000.0}) {
    for (int a = 1; a <= 64; ++a) {
      for (int b = 1; b <= 64; ++b) {
        const DVec3 d{double(a), -double(b), 1.0};  // never parallel to the triangle (its normal is (-1, 1, 1))
        const DVec3 v0 = o + d * k;
        const std::array<DVec3, 3> near = {v0, v0 + DVec3{2.0, 1.0, 1.0}, v0 + DVec3{1.0, 2.0, -1.0}};
        TriangleMeshD mesh;
        for (const DVec3& v : near) mesh.vertices.push_back(v);
        for (const DVec3& v : near) mesh.vertices.push_back(o - (v - o));  // behind the origin: never hit
        mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
        const DoubleScene scene(mesh);
        auto bvh = make_double_accelerator("bvh:leaf_size=1");
        bvh->build(scene);
        auto brute = make_double_accelerator("brute_force");
        brute->build(scene);
        ASSERT_EQ((DVec3(scene.bounds().lo) + DVec3(scene.bounds().hi)) * 0.5, o) << "the anchor is O";
        const AABB box = anchored_float_box(near, o);
        ASSERT_EQ(double(box.lo[0]), k * a) << "v0 lies on the box's edge exactly";
        ASSERT_EQ(double(box.lo[1]), -k * b) << "v0 lies on the box's edge exactly";

        RayD ray;
        ray.origin = o;
        ray.direction = d;
        const HitD expected = brute->intersect(ray);
        ASSERT_TRUE(expected.found()) << "a=" << a << " b=" << b << " k=" << k << ": the ray passes through v0";
        const HitD got = bvh->intersect(ray);
        EXPECT_TRUE(got.found()) << "a=" << a << " b=" << b << " k=" << k << ": the grazed box was culled";
        EXPECT_EQ(got.t, expected.t);
        EXPECT_TRUE(bvh->occluded(ray)) << "a=" << a << " b=" << b << " k=" << k;
        // The plain slab distances (no push) of the x entry and the y exit, as the box test rounds them.
        const PreparedRayD prepared(ray);
        const double x_enter = (double(box.lo[0]) - 0.0) * prepared.inv_direction[0];
        const double y_leave = (double(box.lo[1]) - 0.0) * prepared.inv_direction[1];
        plain_misses += x_enter > y_leave ? 1 : 0;
      }
    }
  }
  // The test means something only if rounding alone loses some of these rays (a = 1, b = 49, for example: 49 times
  // fl(1/49) is 1 - 2^-53).
  EXPECT_GT(plain_misses, 0);
}

TEST(DoubleBvh, BatchesMatchSingleRays) {
  const DoubleScene scene(far_mesh("sphere", {{"level", "3"}}, 10.0));
  auto bvh = make_double_accelerator("bvh");
  bvh->build(scene);
  const std::vector<RayD> rays = testing::mixed_rays(scene.mesh(), 3000, 10.0, 5);
  std::vector<HitD> hits(rays.size());
  std::vector<std::uint8_t> occluded(rays.size());
  bvh->intersect(rays, hits);
  bvh->occluded(rays, occluded);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const HitD one = bvh->intersect(rays[i]);
    EXPECT_EQ(hits[i].prim_id, one.prim_id) << i;
    EXPECT_EQ(hits[i].t, one.t) << i;
    EXPECT_EQ(occluded[i] != 0, one.found()) << i;
  }
  std::vector<HitD> short_output(rays.size() - 1);
  EXPECT_THROW(bvh->intersect(rays, short_output), Error);
}

TEST(DoubleBvh, EmptySceneAndUnbuiltStructuresMissEverything) {
  const DoubleScene empty{TriangleMeshD{}};
  auto bvh = make_double_accelerator("bvh");
  EXPECT_FALSE(bvh->intersect(RayD{}).found());
  bvh->build(empty);
  EXPECT_FALSE(bvh->intersect(RayD{}).found());
  EXPECT_FALSE(bvh->occluded(RayD{}));
}

TEST(DoubleAcceleratorSpecs, NameTheirMistakes) {
  using testing::contains;
  using testing::error_message;
  EXPECT_TRUE(contains(error_message([] { make_double_accelerator("kdtree"); }), "brute_force, bvh"));
  EXPECT_TRUE(contains(error_message([] { make_double_accelerator("bvh:bv=obb"); }), "aabb"));
  EXPECT_TRUE(contains(error_message([] { make_double_accelerator("bvh:leaf_sise=2"); }), "leaf_sise"));
  EXPECT_TRUE(contains(error_message([] { make_double_accelerator("brute_force:x=1"); }), "no options"));
  EXPECT_EQ(make_double_accelerator("bvh:builder=ploc,leaf_size=2")->spec(), "bvh:builder=ploc,leaf_size=2");
}

}  // namespace
}  // namespace rayaccel
