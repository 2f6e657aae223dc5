// Several geometries side by side in one instanced scene, each placed with the exact identity (see
// instanced_accelerator.h): such an instance traces the world ray itself, so
// - a closed mesh split into two geometries along a seam stays watertight: rays through the seam's vertices and
//   edges, and axis rays running in the seam plane with +0 and -0 components, all hit, with exactly brute force's
//   answer over the unsplit mesh (the same kernel on the same ray: bit-identical t, or an exact tie);
// - a triangle mesh, spheres and user primitives in one scene answer as brute force over each geometry alone, the
//   closest over all, each hit naming its geometry and the primitive within it;
// - the bottom level receives the world ray bit for bit (a -0 direction component stays -0), while any other
//   transform maps it.
// For finite rays, mapping through the identity in double changes nothing but the sign of zero components, so the
// seam test passes with mapped rays too; the bit-for-bit test is the one that tells the two paths apart.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "../conformance/oracle.h"
#include "../conformance/test_scenes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/instance/instanced_accelerator.h"

namespace rayaccel {
namespace {

using conformance::brute_force_hits;
using conformance::describe;
using conformance::hit_mismatch;

class ConformanceSideBySide : public ::testing::TestWithParam<std::string> {};

/// The closed box split along the plane x = 0: geometry 0 holds the triangles whose centroid has x < 0, geometry 1
/// the others; both keep every vertex, so seam vertices are the same floats in both. original[g][p] is the unsplit
/// mesh's id of geometry g's primitive p.
struct SplitBox {
  TriangleMesh whole;
  InstancedScene scene;
  std::vector<std::uint32_t> original[2];
};

SplitBox split_box() {
  SplitBox out;
  out.whole = conformance::closed_box_mesh(8);
  TriangleMesh halves[2];
  for (std::uint32_t id = 0; id < out.whole.triangles.size(); ++id) {
    const auto& tri = out.whole.triangles[id];
    const float x = out.whole.vertices[tri[0]].x + out.whole.vertices[tri[1]].x + out.whole.vertices[tri[2]].x;
    const int half = x < 0.0f ? 0 : 1;
    halves[half].triangles.push_back(tri);
    out.original[half].push_back(id);
  }
  for (int half = 0; half < 2; ++half) {
    halves[half].vertices = out.whole.vertices;
    out.scene.add_geometry(Scene::from_mesh(std::move(halves[half]), "half " + std::to_string(half)));
    out.scene.add_instance(static_cast<std::uint32_t>(half), Affine3::identity(), 7 + static_cast<std::uint32_t>(half));
  }
  return out;
}

TEST_P(ConformanceSideBySide, AMeshSplitAlongASeamStaysWatertight) {
  SplitBox box = split_box();
  ASSERT_FALSE(box.original[0].empty());
  ASSERT_FALSE(box.original[1].empty());
  const Scene whole = Scene::from_mesh(box.whole, "closed box");
  InstancedAccelerator accel({GetParam()});
  accel.build(box.scene);
  EXPECT_TRUE(accel.validate().empty());

  // Rays at every vertex and edge midpoint (the seam's among them) from inside, and axis and diagonal rays from
  // points on and off the seam plane, with either sign of zero: every one starts inside the closed box.
  std::vector<Ray> rays = conformance::rays_to_vertices_and_edges(
      box.whole, {{0.0f, 0.0f, 0.0f}, {0.0f, 0.25f, -0.5f}, {0.5f, -0.25f, 0.125f}, {-0.9f, 0.9f, 0.9f}});
  for (const Ray& ray : conformance::axis_parallel_rays({-0.5f, 0.0f, 0.25f})) rays.push_back(ray);
  const std::vector<Hit> reference = brute_force_hits(whole, rays);
  int escapes = 0, faults = 0, seam_hits[2] = {0, 0};
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_TRUE(reference[i].found()) << "brute force leaks " << describe(rays[i]);
    const InstanceHit got = accel.intersect(rays[i]);
    EXPECT_TRUE(accel.occluded(rays[i])) << describe(rays[i]);
    if (!got.found()) {
      if (++escapes <= 5) ADD_FAILURE() << "a ray escapes between the two geometries: " << describe(rays[i]);
      continue;
    }
    ASSERT_LT(got.geom_id, 2u);
    EXPECT_EQ(got.instance, got.geom_id);
    EXPECT_EQ(got.instance_id, 7 + got.geom_id);
    ASSERT_LT(got.prim_id, box.original[got.geom_id].size());
    const Hit as_whole{got.t, box.original[got.geom_id][got.prim_id], got.u, got.v};
    const std::string fault = hit_mismatch(whole, rays[i], reference[i], as_whole);
    if (!fault.empty() && ++faults <= 5) {
      ADD_FAILURE() << fault << ": " << describe(rays[i]) << "\n  expected " << describe(reference[i]) << "\n  got "
                    << describe(as_whole) << " in geometry " << got.geom_id;
    }
    const auto& tri = box.whole.triangles[as_whole.prim_id];
    if (box.whole.vertices[tri[0]].x == 0.0f || box.whole.vertices[tri[1]].x == 0.0f ||
        box.whole.vertices[tri[2]].x == 0.0f) {
      ++seam_hits[got.geom_id];
    }
  }
  EXPECT_EQ(escapes, 0) << "of " << rays.size() << " rays";
  EXPECT_EQ(faults, 0) << "of " << rays.size() << " rays";
  EXPECT_GT(seam_hits[0], 20);  // the seam was really tested, from both sides
  EXPECT_GT(seam_hits[1], 20);
}

TEST_P(ConformanceSideBySide, MeshSpheresAndUserPrimitivesMatchBruteForceOfEach) {
  const AABB unit(Vec3{0.0f}, Vec3{1.0f});
  std::vector<Scene> geometries;
  geometries.push_back(Scene::from_mesh(conformance::random_soup_mesh(300, 0.3f, 21), "soup"));
  geometries.push_back(conformance::random_sphere_scene(150, 22));
  geometries.push_back(conformance::user_sphere_scene(150, 23));
  InstancedScene scene;
  for (const Scene& g : geometries) {
    scene.add_instance(scene.add_geometry(std::make_shared<const Scene>(g)), Affine3::identity());
  }
  InstancedAccelerator accel({GetParam()});
  accel.build(scene);
  EXPECT_TRUE(accel.validate().empty());
  const std::vector<Ray> rays = conformance::random_rays(unit, 2000, 24);
  std::vector<std::vector<Hit>> reference;
  for (const Scene& g : geometries) reference.push_back(brute_force_hits(g, rays));
  std::vector<InstanceHit> batch(rays.size());
  accel.intersect(rays, batch);
  int faults = 0, found[3] = {0, 0, 0};
  for (std::size_t i = 0; i < rays.size(); ++i) {
    float closest = INFINITY;
    for (const auto& r : reference) closest = std::fmin(closest, r[i].t);
    const InstanceHit got = accel.intersect(rays[i]);
    EXPECT_EQ(batch[i].t, got.t);
    EXPECT_EQ(batch[i].geom_id, got.geom_id);
    EXPECT_EQ(accel.occluded(rays[i]), std::isfinite(closest)) << describe(rays[i]);
    std::string fault;
    if (!std::isfinite(closest)) {
      if (got.found()) fault = "a hit where no geometry has one";
    } else if (!got.found() || got.geom_id >= geometries.size()) {
      fault = "missed a hit";
    } else if (!(std::fabs(got.t - closest) <= conformance::kRelativeTTolerance * std::fabs(closest))) {
      fault = "t is not the closest over the geometries";
    } else {
      fault = hit_mismatch(geometries[got.geom_id], rays[i], reference[got.geom_id][i], got.hit());
      EXPECT_EQ(got.instance, got.geom_id);
      ++found[got.geom_id];
    }
    if (!fault.empty() && ++faults <= 5) {
      ADD_FAILURE() << fault << ": " << describe(rays[i]) << "\n  got " << describe(got.hit()) << " in geometry "
                    << got.geom_id;
    }
  }
  EXPECT_EQ(faults, 0) << "of " << rays.size() << " rays";
  for (int g = 0; g < 3; ++g) EXPECT_GT(found[g], 20) << "geometry " << g << " is rarely the closest";
}

INSTANTIATE_TEST_SUITE_P(Conformance, ConformanceSideBySide, ::testing::Values("bvh_wide", "bvh", "kdtree"),
                         [](const auto& param_info) { return std::string(param_info.param); });

/// One user primitive (the unit box's bounds) whose intersect records the ray it was given and reports a hit at
/// t = 1.
Scene recording_geometry(std::shared_ptr<std::vector<PreparedRay>> seen) {
  UserPrimitives prims;
  prims.count = 1;
  prims.bounds = [](std::uint32_t) { return AABB(Vec3{0.0f}, Vec3{1.0f}); };
  prims.intersect = [seen](std::uint32_t id, const PreparedRay& ray, Hit& hit) {
    seen->push_back(ray);
    if (!(ray.t_min < 1.0f && 1.0f <= ray.t_max)) return false;
    hit = Hit{1.0f, id, 0.0f, 0.0f};
    return true;
  };
  prims.normal = [](std::uint32_t, const Vec3&) { return Vec3{0.0f, 0.0f, 1.0f}; };
  return Scene::from_user(std::move(prims), "recording");
}

TEST(InstancedSideBySide, AnIdentityInstanceTracesTheWorldRayBitForBit) {
  auto seen = std::make_shared<std::vector<PreparedRay>>();
  InstancedScene scene;
  scene.add_geometry(recording_geometry(seen));
  scene.add_instance(0, Affine3::identity());
  InstancedAccelerator accel({"bvh"});
  accel.build(scene);
  Ray ray;
  ray.origin = {0.5f, 0.25f, -1.0f};
  ray.direction = {-0.0f, 0.0f, 2.0f};  // a -0 component: mapped through the matrix it would become +0
  ray.t_min = 0.125f;
  const InstanceHit hit = accel.intersect(ray);
  EXPECT_TRUE(hit.found());
  EXPECT_EQ(hit.t, 1.0f);
  ASSERT_FALSE(seen->empty());
  const PreparedRay& got = seen->back();
  EXPECT_TRUE(std::signbit(got.direction.x)) << "the identity instance was given a mapped ray";
  EXPECT_EQ(got.origin.x, 0.5f);
  EXPECT_EQ(got.origin.y, 0.25f);
  EXPECT_EQ(got.origin.z, -1.0f);
  EXPECT_EQ(got.direction.z, 2.0f);
  EXPECT_EQ(got.t_min, 0.125f);

  // Any other transform maps the ray (here a translation by +1 in z: the object sees the origin at z = -2).
  seen->clear();
  scene.set_transform(0, Affine3::translation(0.0, 0.0, 1.0));
  accel.rebuild_top();
  EXPECT_TRUE(accel.intersect(ray).found());
  ASSERT_FALSE(seen->empty());
  EXPECT_EQ(seen->back().origin.z, -2.0f);
}

TEST(InstancedSideBySide, IsIdentityIsExact) {
  EXPECT_TRUE(Affine3::identity().is_identity());
  Affine3 almost = Affine3::identity();
  almost(1, 1) = std::nextafter(1.0, 2.0);
  EXPECT_FALSE(almost.is_identity());
  EXPECT_FALSE(Affine3::translation(0.0, 1e-300, 0.0).is_identity());
  Affine3 negative_zero = Affine3::identity();
  negative_zero(0, 3) = -0.0;
  EXPECT_TRUE(negative_zero.is_identity());  // -0 translates by nothing
}

}  // namespace
}  // namespace rayaccel
