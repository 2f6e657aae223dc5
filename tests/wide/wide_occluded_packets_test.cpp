// The any-hit packet traversal of bvh_wide (occluded_packets, eight rays at a time, a ray leaving its packet at its
// first hit): ray for ray the answers of occluded() on the Stanford bunny for coherent rays (light rays of tiled
// camera rays, the camera rays themselves) and incoherent ones (ambient-occlusion rays in random directions, rays
// between random points), with void lanes (NaN components, t_min > t_max), empty intervals (t_max = 0), rays starting
// on triangle edges, rays through shared edges (the lanes the float path leaves to the scalar kernel) and partial
// packets, for every width and instruction set; and the default occluded_packets() of a structure without a packet
// traversal.
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "../bvh/bvh_test_scenes.h"
#include "packet_test_rays.h"
#include "../shared_scenes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/render/camera.h"
#include "rayaccel/render/workloads.h"
#include "rayaccel/scene/import.h"

namespace rayaccel::wide {
namespace {

/// occluded_packets() against occluded() one ray at a time, ray for ray; returns how many rays are occluded.
std::size_t expect_packets_match_occluded(const Accelerator& accel, const std::vector<Ray>& rays,
                                          const std::string& what) {
  std::vector<std::uint8_t> packets(rays.size(), 2);  // 2: never written
  accel.occluded_packets(rays, packets);
  std::size_t occluded = 0;
  int faults = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const std::uint8_t single = accel.occluded(rays[i]) ? 1 : 0;
    occluded += single;
    if (packets[i] != single && ++faults <= 5) {
      ADD_FAILURE() << accel.spec() << " / " << what << " ray " << i << " (packet " << i / 8 << "): packet says "
                    << int(packets[i]) << ", occluded() says " << int(single);
    }
  }
  EXPECT_EQ(faults, 0) << accel.spec() << " / " << what;
  return occluded;
}

class WideOccludedPackets : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const auto path = testing::shared_scenes_dir() / "bunny.ply";
    if (std::filesystem::exists(path)) bunny_ = new Scene(load_scene(path.string()));
  }
  static void TearDownTestSuite() {
    delete bunny_;
    bunny_ = nullptr;
  }
  void SetUp() override {
    RAYACCEL_NEED_SHARED_FILE(testing::shared_scenes_dir() / "bunny.ply");
    for (const char* spec : kPacketSpecs) {
      structures_.push_back(make_accelerator(spec));
      structures_.back()->build(*bunny_);
    }
  }
  static Scene* bunny_;
  std::vector<std::unique_ptr<Accelerator>> structures_;
};
Scene* WideOccludedPackets::bunny_ = nullptr;

TEST_F(WideOccludedPackets, CoherentLightAndCameraRaysMatchOccluded) {
  const Scene& scene = *bunny_;
  const std::vector<Ray> camera = tiled_camera_rays(scene, 67, 45);  // neither a multiple of 4 nor of 2
  std::vector<Hit> hits(camera.size());
  structures_.front()->intersect(camera, hits);
  // A point light above and in front of the bunny: rays from the lit side leave unoccluded, the others not.
  const AABB box = scene.bounds();
  const Vec3 light = box.center() + Vec3{0.3f, 1.5f, 1.0f} * box.extent();
  std::vector<Ray> to_light = light_rays(scene, camera, hits, light);  // one per camera hit
  const std::size_t camera_hits = to_light.size();
  if (to_light.size() % 8 == 0) to_light.pop_back();  // a partial last packet
  for (const auto& accel : structures_) {
    const std::size_t occluded = expect_packets_match_occluded(*accel, to_light, "light rays");
    EXPECT_GT(occluded, to_light.size() / 20) << accel->spec() << ": some light rays should be blocked";
    EXPECT_LT(occluded, to_light.size() - to_light.size() / 20) << accel->spec() << ": most should reach the light";
    const std::size_t seen = expect_packets_match_occluded(*accel, camera, "camera rays");
    EXPECT_EQ(seen, camera_hits) << accel->spec() << ": a camera ray is occluded when it hits";
  }
}

TEST_F(WideOccludedPackets, IncoherentRaysMatchOccluded) {
  const Scene& scene = *bunny_;
  const std::vector<Ray> camera = tiled_camera_rays(scene, 48, 32);
  std::vector<Hit> hits(camera.size());
  structures_.front()->intersect(camera, hits);
  const float diagonal = length(scene.bounds().extent());
  // Ambient-occlusion rays: random directions over each hit's hemisphere (rays of different axes in one packet).
  const std::vector<Ray> ambient = shadow_rays(scene, camera, hits, 0.2f * diagonal, 5);
  // Segments between random points of a box a little larger than the bunny's, 1003 of them (a partial packet).
  std::mt19937 rng(11);
  const AABB box = scene.bounds();
  std::uniform_real_distribution<float> unit(-0.1f, 1.1f);
  const auto point = [&] {
    return box.lo + Vec3{unit(rng), unit(rng), unit(rng)} * box.extent();
  };
  std::vector<Ray> segments;
  for (int i = 0; i < 1003; ++i) {
    const Vec3 from = point();
    segments.push_back({from, 0.0f, point() - from, 1.0f});
  }
  for (const auto& accel : structures_) {
    const std::size_t blocked = expect_packets_match_occluded(*accel, ambient, "ambient-occlusion rays");
    EXPECT_GT(blocked, 0u) << accel->spec();
    EXPECT_LT(blocked, ambient.size()) << accel->spec();
    const std::size_t crossing = expect_packets_match_occluded(*accel, segments, "random segments");
    EXPECT_GT(crossing, 0u) << accel->spec();
    EXPECT_LT(crossing, segments.size()) << accel->spec();
  }
}

TEST_F(WideOccludedPackets, VoidLanesEmptyIntervalsAndRaysFromEdgesMatchOccluded) {
  const Scene& scene = *bunny_;
  const std::vector<Ray> camera = tiled_camera_rays(scene, 32, 16);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Ray> rays = camera;
  // In coherent packets (the fast path, with some lanes inactive): NaN in each component, t_min > t_max, t_max = 0,
  // t_min == t_max, a NaN bound.
  std::vector<std::size_t> never;  // rays that cannot be occluded
  for (std::size_t p = 0; p < 10; ++p) {
    Ray& r = rays[8 * p + (p * 3) % 8];  // a different lane in each packet
    switch (p) {
      case 0: r.origin.x = nan; break;
      case 1: r.origin.z = nan; break;
      case 2: r.direction.y = nan; break;
      case 3: r.t_min = nan; break;
      case 4: r.t_max = nan; break;
      case 5:
        r.t_min = 3.0f;
        r.t_max = 2.0f;
        break;
      case 6: r.t_max = 0.0f; break;
      case 7: r.t_min = r.t_max = 1.0f; break;
      case 8: r.direction = {0.0f, 0.0f, 0.0f}; break;
      default: r.t_min = -1.0f; break;  // a ray starting behind its origin: the packet goes ray by ray
    }
    if (p != 9) never.push_back(8 * p + (p * 3) % 8);
  }
  // Rays starting on an edge of a bunny triangle (its midpoint), towards a point light and away from it: the
  // triangle itself lies at t = 0, outside (t_min, t_max].
  const AABB box = scene.bounds();
  const Vec3 light = box.center() + Vec3{0.0f, 2.0f, 0.0f} * box.extent();
  for (std::uint32_t id = 0, n = 0; id < scene.primitive_count() && n < 200; id += 97) {
    if (!scene.is_valid(id)) continue;
    const auto& v = scene.triangle(id);
    const Vec3 on_edge = (v[n % 3] + v[(n + 1) % 3]) * 0.5f;
    rays.push_back({on_edge, 0.0f, light - on_edge, 1.0f});
    rays.push_back({on_edge, 0.0f, on_edge - light, 1.0f});
    ++n;
  }
  // Coherent rays exactly through the midpoints of bunny edges from one point outside (shared edges: the lanes the
  // float path leaves to the scalar kernel), ending just beyond them or far behind.
  const Vec3 eye = box.center() + Vec3{0.0f, 0.0f, 3.0f} * box.extent();
  for (std::uint32_t id = 1; id < scene.primitive_count() && rays.size() % 8 != 5; id += 31) {
    if (!scene.is_valid(id)) continue;
    const auto& v = scene.triangle(id);
    const Vec3 target = (v[0] + v[1]) * 0.5f;
    rays.push_back({eye, 0.0f, target - eye, id % 2 ? 1.0f : 4.0f});
  }
  ASSERT_EQ(rays.size() % 8, 5u);
  for (const auto& accel : structures_) {
    const std::size_t occluded = expect_packets_match_occluded(*accel, rays, "odd rays");
    EXPECT_GT(occluded, 0u) << accel->spec();
    std::vector<std::uint8_t> packets(rays.size());
    accel->occluded_packets(rays, packets);
    for (std::size_t i : never) EXPECT_EQ(packets[i], 0) << accel->spec() << " ray " << i;
  }
}

TEST(WideOccludedPacketsGrid, RaysThroughSharedEdgesAndVerticesNeverSlipThrough) {
  // A flat grid of n x n squares in the plane y = 0 and coherent rays from one point above it, aimed at its interior
  // vertices and edge midpoints: every ray is occluded, in packets as one by one (watertight across the lanes the
  // float path leaves to the scalar kernel); rays ending just short of the plane are not.
  const std::uint32_t n = 16;
  const Scene scene = Scene::from_mesh(bvh_test::grid_mesh(n), "grid");
  const Vec3 eye{0.37f, 3.0f, 0.41f};
  std::vector<Ray> through, short_of;
  const float step = 2.0f / static_cast<float>(n);
  for (std::uint32_t j = 1; j < n; ++j) {
    for (std::uint32_t i = 1; i < 2 * n; ++i) {
      const Vec3 target{-1.0f + 0.5f * step * static_cast<float>(i), 0.0f, -1.0f + step * static_cast<float>(j)};
      through.push_back({eye, 0.0f, target - eye, 1.0f});
      short_of.push_back({eye, 0.0f, target - eye, 0.999f});
    }
  }
  for (const char* spec : kPacketSpecs) {
    auto accel = make_accelerator(spec);
    accel->build(scene);
    EXPECT_EQ(expect_packets_match_occluded(*accel, through, "through edges"), through.size()) << spec;
    EXPECT_EQ(expect_packets_match_occluded(*accel, short_of, "short of edges"), 0u) << spec;
  }
}

TEST(WideOccludedPacketsGrid, BatchSizesAndEmptyScenes) {
  const Scene scene = Scene::from_mesh(bvh_test::grid_mesh(4), "grid");
  const Scene empty = Scene::from_mesh({}, "empty");
  const std::vector<Ray> rays(9, Ray{{0.0f, 1.0f, 0.0f}, 0.0f, {0.0f, -1.0f, 0.0f}, 2.0f});
  for (const char* spec : kPacketSpecs) {
    auto accel = make_accelerator(spec);
    accel->build(scene);
    std::vector<std::uint8_t> short_output(rays.size() - 1);
    EXPECT_THROW(accel->occluded_packets(rays, short_output), Error) << spec;
    accel->occluded_packets({}, {});
    accel->build(empty);
    std::vector<std::uint8_t> out(rays.size(), 1);
    accel->occluded_packets(rays, out);
    for (std::uint8_t o : out) EXPECT_EQ(o, 0) << spec;
  }
}

TEST(OccludedPacketsDefault, StructuresWithoutPacketsAnswerOneByOne) {
  // The default occluded_packets(): the occluded() batch, with its size checks.
  const Scene scene = Scene::from_mesh(bvh_test::grid_mesh(8), "grid");
  std::vector<Ray> rays;
  for (int i = 0; i < 21; ++i) {
    const float x = -1.2f + 0.12f * static_cast<float>(i);  // some beyond the grid's edge at |x| = 1
    rays.push_back({{x, 1.0f, 0.3f}, 0.0f, {0.0f, -1.0f, 0.0f}, i % 3 == 0 ? 0.5f : 2.0f});
  }
  for (const char* spec : {"bvh", "kdtree", "brute_force"}) {
    auto accel = make_accelerator(spec);
    accel->build(scene);
    const std::size_t occluded = expect_packets_match_occluded(*accel, rays, "grid rays");
    EXPECT_GT(occluded, 0u) << spec;
    EXPECT_LT(occluded, rays.size()) << spec;
    std::vector<std::uint8_t> short_output(rays.size() - 1);
    EXPECT_THROW(accel->occluded_packets(rays, short_output), Error) << spec;
  }
}

}  // namespace
}  // namespace rayaccel::wide
