// The packet traversal of bvh_wide (intersect_packets, eight rays at a time): the same closest hits as single rays on
// coherent camera rays (its fast path: one triangle against the packet's rays), on packets that take the ray-by-ray
// fallbacks (rays of different axes, t_min < 0, a subnormal origin coordinate), on void and missing lanes, and on
// rays through shared edges and vertices (the lanes the float path leaves to the scalar kernel), for every width and
// instruction set.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "../bvh/bvh_test_scenes.h"
#include "packet_test_rays.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/render/camera.h"
#include "rayaccel/render/workloads.h"
#include "rayaccel/scene/builtin_scenes.h"

namespace rayaccel::wide {
namespace {

/// Packet answers against single-ray answers: the same t bit for bit, and the same primitive, u and v unless another
/// primitive ties at exactly that t (the packet may meet the tied primitives in another order). Returns the hits.
int expect_packets_match_single_rays(const Accelerator& accel, const std::vector<Ray>& rays,
                                     const std::string& what) {
  std::vector<Hit> packets(rays.size());
  accel.intersect_packets(rays, packets);
  int hits = 0, faults = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hit single = accel.intersect(rays[i]);
    const Hit& p = packets[i];
    hits += single.found() ? 1 : 0;
    const bool same_t = std::bit_cast<std::uint32_t>(p.t) == std::bit_cast<std::uint32_t>(single.t);
    const bool same = same_t && (p.prim_id != single.prim_id || (p.u == single.u && p.v == single.v));
    if (!same && ++faults <= 5) {
      ADD_FAILURE() << accel.spec() << " / " << what << " ray " << i << " (packet " << i / 8 << "): packet hit "
                    << p.prim_id << " at " << p.t << ", single ray " << single.prim_id << " at " << single.t;
    }
  }
  EXPECT_EQ(faults, 0) << accel.spec() << " / " << what;
  return hits;
}

TEST(WidePackets, CoherentCameraRaysMatchSingleRays) {
  for (const char* scene_name : {"default", "teapot_stadium", "soup"}) {
    const Scene scene = make_builtin_scene(scene_name);
    const std::vector<Ray> rays = tiled_camera_rays(scene, 61, 43);  // neither a multiple of 4 nor of 2
    for (const char* spec : kPacketSpecs) {
      auto accel = make_accelerator(spec);
      accel->build(scene);
      const int hits = expect_packets_match_single_rays(*accel, rays, scene_name);
      EXPECT_GT(hits, static_cast<int>(rays.size()) / 10) << spec << " / " << scene_name;
    }
  }
}

TEST(WidePackets, PacketsThatFallBackToSingleRays) {
  const Scene scene = make_builtin_scene("default");
  const std::vector<Ray> camera = tiled_camera_rays(scene, 16, 8);
  const AABB box = scene.bounds();
  const Vec3 center = (box.lo + box.hi) * 0.5f;
  std::vector<Ray> rays;
  // Rays of different axes in one packet: from the box's center along each axis, both ways, and two diagonals.
  for (Vec3 d : {Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -1, 0}, Vec3{0, 0, 1}, Vec3{0, 0, -1},
                 Vec3{1, 1, 1}, Vec3{-1, 0.5f, 0.25f}}) {
    rays.push_back({center, 0.0f, d, std::numeric_limits<float>::infinity()});
  }
  // A coherent packet with one ray starting behind its origin (t_min < 0).
  for (int i = 0; i < 8; ++i) {
    Ray r = camera[i];
    if (i == 5) r.t_min = -2.0f;
    rays.push_back(r);
  }
  // A coherent packet with a subnormal origin coordinate in one ray (BoxTestOrigin's shift).
  for (int i = 0; i < 8; ++i) {
    Ray r = camera[8 + i];
    if (i == 2) r.origin.y = r.origin.y == 0.0f ? 1e-40f : r.origin.y;
    rays.push_back(r);
  }
  // Void lanes among coherent rays: NaN and zero directions, an infinite origin, t_max < t_min, NaN t_max.
  for (int i = 0; i < 8; ++i) {
    Ray r = camera[16 + i];
    if (i == 1) r.direction.x = std::numeric_limits<float>::quiet_NaN();
    if (i == 3) r.direction = {0.0f, 0.0f, 0.0f};
    if (i == 4) r.origin.z = std::numeric_limits<float>::infinity();
    if (i == 6) r.t_max = -1.0f;
    if (i == 7) r.t_max = std::numeric_limits<float>::quiet_NaN();
    rays.push_back(r);
  }
  // A packet of void rays only, and a last partial packet of five.
  for (int i = 0; i < 8; ++i) rays.push_back({center, 0.0f, {0.0f, 0.0f, 0.0f}, 1.0f});
  for (int i = 0; i < 5; ++i) rays.push_back(camera[32 + i]);
  for (const char* spec : kPacketSpecs) {
    auto accel = make_accelerator(spec);
    accel->build(scene);
    expect_packets_match_single_rays(*accel, rays, "fallback packets");
    std::vector<Hit> packets(rays.size());
    accel->intersect_packets(rays, packets);
    for (int i = 32; i < 40; ++i) EXPECT_FALSE(packets[i].found()) << spec << " void ray " << i;
    for (int i : {17, 19, 20, 22, 23}) EXPECT_FALSE(packets[i + 8].found()) << spec << " void lane " << i + 8;
  }
}

TEST(WidePackets, RaysThroughSharedEdgesAndVerticesNeverSlipThrough) {
  // A flat grid of n x n squares (two triangles each) in the plane y = 0 over [-1, 1]^2, and coherent rays from one
  // point above it aimed at its interior vertices and the midpoints of its edges: every ray must hit, in packets as
  // one by one.
  const std::uint32_t n = 16;
  const Scene scene = Scene::from_mesh(bvh_test::grid_mesh(n), "grid");
  const Vec3 eye{0.37f, 3.0f, 0.41f};
  std::vector<Ray> rays;
  const float step = 2.0f / static_cast<float>(n);
  for (std::uint32_t j = 1; j < n; ++j) {
    for (std::uint32_t i = 1; i < 2 * n; ++i) {
      const Vec3 target{-1.0f + 0.5f * step * static_cast<float>(i), 0.0f, -1.0f + step * static_cast<float>(j)};
      rays.push_back({eye, 0.0f, target - eye, std::numeric_limits<float>::infinity()});
    }
  }
  for (const char* spec : kPacketSpecs) {
    auto accel = make_accelerator(spec);
    accel->build(scene);
    const int hits = expect_packets_match_single_rays(*accel, rays, "edges and vertices");
    EXPECT_EQ(hits, static_cast<int>(rays.size())) << spec;
    std::vector<Hit> packets(rays.size());
    accel->intersect_packets(rays, packets);
    for (std::size_t i = 0; i < rays.size(); ++i) EXPECT_TRUE(packets[i].found()) << spec << " ray " << i;
  }
}

}  // namespace
}  // namespace rayaccel::wide
