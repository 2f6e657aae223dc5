// The queries on the shared meshes: the dragon is closed (every edge shared by an even number of triangles), so rays
// exactly through its vertices cross it an even number of times, with every structure as with brute force, and its
// crossing-parity inside test agrees with the generalised winding number, computed independently.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "../conformance/test_scenes.h"
#include "../shared_scenes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/query/closed_mesh.h"
#include "rayaccel/query/inside.h"
#include "rayaccel/scene/import.h"

namespace rayaccel {
namespace {

using conformance::Rng;

TEST(SlowQueries, DragonIsCrossedEvenlyThroughItsVerticesAndParityAgreesWithWindingNumbers) {
  const auto path = testing::shared_scenes_dir() / "dragon.ply";
  RAYACCEL_NEED_SHARED_FILE(path);
  const Scene scene = load_scene(path.string());
  ASSERT_TRUE(check_closed(scene).closed());
  auto brute = make_accelerator("brute_force");
  brute->build(scene);
  std::vector<std::unique_ptr<Accelerator>> structures;
  for (const char* spec : {"bvh", "bvh_wide"}) {
    structures.push_back(make_accelerator(spec));
    structures.back()->build(scene);
  }
  // Axis-parallel rays exactly through vertices of valid triangles, from outside the box.
  Rng rng(12);
  const AABB& box = scene.bounds();
  std::vector<Hit> expected, got;
  std::size_t crossings = 0;
  for (int i = 0; i < 60; ++i) {
    std::uint32_t id;
    do id = rng.below(scene.primitive_count());
    while (!scene.is_valid(id));
    const Vec3 v = scene.triangle(id)[i % 3];
    const int axis = i % 3;
    Vec3 origin = v, direction{0, 0, 0};
    origin[axis] = box.hi[axis] + 1.0f;
    direction[axis] = -1.0f;
    const Ray ray{origin, 0.0f, direction, std::numeric_limits<float>::infinity()};
    const std::size_t count = structures[1]->all_hits(ray, expected);
    EXPECT_EQ(count % 2, 0u) << "vertex of triangle " << id;
    crossings += count;
    if (i % 4 != 0) continue;  // brute force (a million triangle tests a ray) on every fourth ray
    brute->all_hits(ray, expected);
    for (const auto& accel : structures) {
      accel->all_hits(ray, got);
      ASSERT_EQ(got.size(), expected.size()) << accel->spec();
      for (std::size_t k = 0; k < got.size(); ++k) {
        EXPECT_EQ(got[k].prim_id, expected[k].prim_id) << accel->spec();
        EXPECT_EQ(got[k].t, expected[k].t) << accel->spec();
      }
    }
  }
  EXPECT_GT(crossings, 60u);

  // Points in the box: parity (3 and 7 rays) against the winding number (> 1/2 inside).
  std::vector<Vec3> points;
  for (int i = 0; i < 24; ++i) points.push_back(rng.in_box(box));
  std::vector<std::uint8_t> inside3(points.size()), inside7(points.size());
  inside_by_parity(*structures[1], points, inside3);
  inside_by_parity(*structures[0], points, inside7, {.ray_count = 7});
  std::vector<double> winding(points.size());
  winding_numbers(scene, points, winding);
  std::size_t inside_count = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(inside3[i], inside7[i]) << i;
    EXPECT_EQ(inside3[i] != 0, winding[i] > 0.5) << i << ": winding number " << winding[i];
    inside_count += inside3[i];
  }
  EXPECT_GT(inside_count, 0u);
}

}  // namespace
}  // namespace rayaccel
