// The C API answers as the C++ API does, bit for bit: two meshes through rayaccel_scene_add_mesh against the same
// meshes merged by scene_from_meshes(), for every registered structure (default options), single rays, batches and
// packets, with geometry ids and per-mesh primitive ids from the GeometryTable.
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "rayaccel/accel/registry.h"
#include "rayaccel/rayaccel_c.h"
#include "rayaccel/scene/geometry_table.h"

namespace rayaccel {
namespace {

TriangleMesh random_mesh(std::uint32_t triangles, float offset, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> coord(-1.0f, 1.0f);
  TriangleMesh mesh;
  for (std::uint32_t i = 0; i < triangles + 2; ++i) mesh.vertices.push_back({coord(rng) + offset, coord(rng), coord(rng)});
  std::uniform_int_distribution<std::uint32_t> index(0, triangles + 1);
  for (std::uint32_t i = 0; i < triangles; ++i) mesh.triangles.push_back({index(rng), index(rng), index(rng)});
  return mesh;
}

std::vector<Ray> random_rays(std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> coord(-2.0f, 2.5f);
  std::vector<Ray> rays(count);
  for (Ray& r : rays) {
    r.origin = {coord(rng), coord(rng), coord(rng)};
    r.direction = Vec3{coord(rng), coord(rng), coord(rng)} - r.origin * 0.5f;
    if (rng() % 5 == 0) r.t_max = 0.7f;
  }
  return rays;
}

void expect_same(const Hit& cpp, const rayaccel_hit& c, const GeometryTable& table, std::size_t i) {
  SCOPED_TRACE("ray " + std::to_string(i));
  EXPECT_EQ(std::memcmp(&cpp.t, &c.t, 4), 0);
  EXPECT_EQ(std::memcmp(&cpp.u, &c.u, 4), 0);
  EXPECT_EQ(std::memcmp(&cpp.v, &c.v, 4), 0);
  if (cpp.found()) {
    EXPECT_EQ(c.geom_id, table.geometry_of(cpp.prim_id));
    EXPECT_EQ(table.first_primitive(c.geom_id) + c.prim_id, cpp.prim_id);
  } else {
    EXPECT_EQ(c.geom_id, RAYACCEL_INVALID_ID);
    EXPECT_EQ(c.prim_id, RAYACCEL_INVALID_ID);
  }
}

TEST(CApi, AnswersAsTheCppApiForEveryStructure) {
  const std::vector<TriangleMesh> meshes = {random_mesh(150, 0.0f, 1), random_mesh(90, 1.0f, 2)};
  GeometryTable table;
  const Scene scene = scene_from_meshes(meshes, table);
  ASSERT_EQ(table.geometry_count(), 2u);

  rayaccel_scene* c_scene = nullptr;
  ASSERT_EQ(rayaccel_scene_new(&c_scene), RAYACCEL_OK);
  for (std::uint32_t k = 0; k < meshes.size(); ++k) {
    std::uint32_t geom = 99;
    ASSERT_EQ(rayaccel_scene_add_mesh(c_scene, &meshes[k].vertices[0].x, meshes[k].vertices.size(),
                                      meshes[k].triangles[0].data(), meshes[k].triangles.size(), &geom),
              RAYACCEL_OK);
    EXPECT_EQ(geom, k);
  }
  const std::vector<Ray> rays = random_rays(400, 3);
  static_assert(sizeof(Vec3) == 12 && sizeof(Ray) == sizeof(rayaccel_ray));
  std::vector<rayaccel_ray> c_rays(rays.size());
  std::memcpy(c_rays.data(), rays.data(), rays.size() * sizeof(Ray));

  int hits_in_each_mesh[2] = {0, 0};
  for (const AcceleratorInfo& info : accelerator_registry()) {
    if (info.comparison) continue;
    SCOPED_TRACE(info.name);
    const auto cpp = make_accelerator(info.name);
    cpp->build(scene);
    std::vector<Hit> expected(rays.size());
    cpp->intersect(rays, expected);
    std::vector<std::uint8_t> expected_occluded(rays.size());
    cpp->occluded(rays, expected_occluded);

    rayaccel_accel* accel = nullptr;
    ASSERT_EQ(rayaccel_accel_new(c_scene, info.name.c_str(), &accel), RAYACCEL_OK) << rayaccel_last_error();
    std::vector<rayaccel_hit> batch(rays.size()), packets(rays.size());
    ASSERT_EQ(rayaccel_intersect(accel, c_rays.data(), c_rays.size(), batch.data()), RAYACCEL_OK);
    ASSERT_EQ(rayaccel_intersect_packets(accel, c_rays.data(), c_rays.size(), packets.data()), RAYACCEL_OK);
    std::vector<std::uint8_t> occluded(rays.size()), occluded_packets(rays.size());
    ASSERT_EQ(rayaccel_occluded(accel, c_rays.data(), c_rays.size(), occluded.data()), RAYACCEL_OK);
    ASSERT_EQ(rayaccel_occluded_packets(accel, c_rays.data(), c_rays.size(), occluded_packets.data()), RAYACCEL_OK);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      expect_same(expected[i], batch[i], table, i);
      rayaccel_hit one;
      ASSERT_EQ(rayaccel_intersect1(accel, &c_rays[i], &one), RAYACCEL_OK);
      expect_same(expected[i], one, table, i);
      EXPECT_EQ(std::memcmp(&packets[i].t, &batch[i].t, 4), 0);  // packets: the same t (a tie may name another)
      int occ = -1;
      ASSERT_EQ(rayaccel_occluded1(accel, &c_rays[i], &occ), RAYACCEL_OK);
      EXPECT_EQ(occ, expected_occluded[i]);
      EXPECT_EQ(occluded[i], expected_occluded[i]);
      EXPECT_EQ(occluded_packets[i], expected_occluded[i]);
      if (batch[i].geom_id < 2) ++hits_in_each_mesh[batch[i].geom_id];
    }
    rayaccel_accel_release(accel);
  }
  EXPECT_GT(hits_in_each_mesh[0], 0);
  EXPECT_GT(hits_in_each_mesh[1], 0);
  rayaccel_scene_release(c_scene);
}

TEST(CApi, NoExceptionCrossesTheBoundary) {
  rayaccel_scene* scene = nullptr;
  ASSERT_EQ(rayaccel_scene_new(&scene), RAYACCEL_OK);
  rayaccel_accel* accel = nullptr;
  EXPECT_EQ(rayaccel_accel_new(scene, "kdtree:leaf_size=banana", &accel), RAYACCEL_INVALID_ARGUMENT);
  EXPECT_NE(std::string(rayaccel_last_error()).find("leaf_size"), std::string::npos) << rayaccel_last_error();
  EXPECT_EQ(accel, nullptr);
  // An empty scene builds and misses every ray.
  ASSERT_EQ(rayaccel_accel_new(scene, "bvh_wide", &accel), RAYACCEL_OK);
  const rayaccel_ray ray = {0, 0, 0, 0, 0, 0, 1, 1e30f};
  rayaccel_hit hit;
  ASSERT_EQ(rayaccel_intersect1(accel, &ray, &hit), RAYACCEL_OK);
  EXPECT_EQ(hit.prim_id, RAYACCEL_INVALID_ID);
  rayaccel_accel_release(accel);
  rayaccel_scene_release(scene);
}

}  // namespace
}  // namespace rayaccel
