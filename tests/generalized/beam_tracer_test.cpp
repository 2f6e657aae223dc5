// Beams against the rays they stand for: every pixel's hit from trace_beams() must be bit for bit the structure's own
// intersect() (prim, t, u, v), over every registered variant with beams (every BVH volume and builder, the wide BVH at
// both widths, the kd-tree), by float frusta (bvh_wide's rays in packets and one by one) and by double-precision
// beams, on built-in stress scenes,
// a mesh whose edges and vertices lie exactly on pixel rays, a scene where a front triangle hides others, and the bunny.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <map>
#include <utility>
#include <string>
#include <vector>

#include "generalized_specs.h"
#include "../shared_scenes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/generalized/generalized_rays.h"
#include "rayaccel/render/camera.h"
#include "rayaccel/scene/builtin_scenes.h"
#include "rayaccel/scene/import.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel {
namespace {

using generalized::BeamOptions;
using generalized::BeamResult;
using generalized::PixelRays;

PixelRays pixels_of(const CameraFrame& frame) {
  return {frame.width, frame.height, [frame](float x, float y) { return frame.ray_at(x, y); }, {}};
}

/// Counts pixels whose beam hit differs from intersect() in any bit; names the first few.
int differences(const Accelerator& accel, const CameraFrame& frame, const BeamResult& result, std::string& report) {
  int count = 0;
  for (int y = 0; y < frame.height; ++y) {
    for (int x = 0; x < frame.width; ++x) {
      const Hit want = accel.intersect(frame.ray(x, y));
      const Hit got = result.hits[std::size_t(y) * std::size_t(frame.width) + std::size_t(x)];
      const bool same = want.prim_id == got.prim_id && std::bit_cast<std::uint32_t>(want.t) == std::bit_cast<std::uint32_t>(got.t) &&
                        std::bit_cast<std::uint32_t>(want.u) == std::bit_cast<std::uint32_t>(got.u) &&
                        std::bit_cast<std::uint32_t>(want.v) == std::bit_cast<std::uint32_t>(got.v);
      if (!same && ++count <= 5) {
        report += "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): intersect prim " +
                  std::to_string(want.prim_id) + " t " + std::to_string(want.t) + ", beams prim " +
                  std::to_string(got.prim_id) + " t " + std::to_string(got.t) + "\n";
      }
    }
  }
  return count;
}

/// A grid of unit squares (two triangles each, diagonals alternating) on z = 0 around the origin, seen from straight
/// above with an odd image: the middle row's and column's rays lie exactly in the planes x = 0 and y = 0, so they meet
/// edges and vertices exactly (the middle pixel's ray goes through the vertex at the origin).
Scene edge_grid() {
  TriangleMesh mesh;
  const int n = 8;
  for (int j = -n; j <= n; ++j) {
    for (int i = -n; i <= n; ++i) mesh.vertices.push_back({float(i), float(j), 0.0f});
  }
  const auto id = [&](int i, int j) { return std::uint32_t((j + n) * (2 * n + 1) + (i + n)); };
  for (int j = -n; j < n; ++j) {
    for (int i = -n; i < n; ++i) {
      if ((i + j) % 2 == 0) {
        mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        mesh.triangles.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  }
  return Scene::from_mesh(std::move(mesh), "edge_grid");
}

/// Two large quads across the view with small triangles behind them and one in front of a part: beams whose front
/// triangle hides the rest.
Scene occluders() {
  TriangleMesh mesh;
  const auto quad = [&](float x0, float y0, float x1, float y1, float z) {
    const auto b = std::uint32_t(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}});
    mesh.triangles.push_back({b, b + 1, b + 2});
    mesh.triangles.push_back({b, b + 2, b + 3});
  };
  quad(-4, -4, 0.2f, 4, 0);
  quad(0.1f, -4, 4, 4, -0.5f);
  for (int k = 0; k < 40; ++k) {
    const float x = -3.5f + 0.17f * k, y = -3.0f + 0.13f * k;
    quad(x, y, x + 0.3f, y + 0.2f, -2.0f - 0.01f * k);
  }
  quad(-1.0f, -1.0f, -0.5f, -0.2f, 1.0f);
  return Scene::from_mesh(std::move(mesh), "occluders");
}

struct Case {
  std::string name;
  Scene scene;
  Camera camera;
  int width, height;
};

std::vector<Case> stress_cases() {
  std::vector<Case> cases;
  cases.push_back({"edge_grid", edge_grid(), Camera{{0, 0, 12}, {0, 0, 0}, {0, 1, 0}, 60.0f}, 33, 33});
  cases.push_back({"occluders", occluders(), Camera{{0.3f, 0.2f, 8}, {0, 0, 0}, {0, 1, 0}, 50.0f}, 48, 40});
  // Reduced sizes keep the suite fast over every variant; still thousands of primitives each.
  const std::vector<std::pair<const char*, std::map<std::string, std::string>>> builtins = {
      {"sierpinski", {{"level", "5"}}}, {"slivers", {{"count", "3000"}}}, {"soup", {{"count", "3000"}}},
      {"default", {}}, {"sphereflake", {{"level", "3"}}}};
  for (const auto& [name, params] : builtins) {
    Scene scene = make_builtin_scene(name, params);
    const Camera camera = Camera::framing(scene.bounds());
    cases.push_back({name, std::move(scene), camera, 40, 36});
  }
  return cases;
}

class BeamIdentity : public ::testing::TestWithParam<std::string> {};

TEST_P(BeamIdentity, EveryPixelMatchesIntersectOnStressScenes) {
  generalized::BeamStats total;
  bool packets_run = false;  // bvh_wide with eight-wide nodes: the frustum's rays go in packets
  for (Case& c : stress_cases()) {
    auto accel = make_accelerator(GetParam());
    accel->build(c.scene);
    const auto rays = generalized::make_generalized_rays(*accel, c.scene);
    const CameraFrame frame = c.camera.frame(c.width, c.height);
    // Defaults, and odd tiles split as far as they go (down to single pixels, each level from its entry point); the
    // wide BVH both by its SIMD frustum (the default) and by the double-precision beam tests.
    std::vector<BeamOptions> configs = {BeamOptions{},
                                        BeamOptions{.tile_size = 7, .min_tile = 1, .max_candidates_per_pixel = 1e9f}};
    // Every structure by its float frustum (the default) and by the double-precision beam tests; bvh_wide's frustum
    // rays also one by one (with counts) besides in packets.
    for (std::size_t i = 0, n = configs.size(); i < n; ++i) {
      configs.push_back(configs[i]);
      configs.back().frustum = false;
      if (GetParam().starts_with("bvh_wide")) {
        configs.push_back(configs[i]);
        configs.back().packets = false;
      }
    }
    const auto* wide = dynamic_cast<const wide::WideBvh*>(accel.get());
    packets_run = packets_run || (wide != nullptr && wide->has_packet_traversal());
    // The first configuration again with the rays and hits given by the caller (a bench's timed form).
    std::vector<Ray> pixel_rays;
    for (int y = 0; y < frame.height; ++y) {
      for (int x = 0; x < frame.width; ++x) pixel_rays.push_back(frame.ray(x, y));
    }
    {
      PixelRays given = pixels_of(frame);
      given.rays = pixel_rays;
      BeamResult result;
      result.hits.resize(pixel_rays.size());
      result.stats = rays->trace_beams(given, configs[0], result.hits);
      std::string report;
      EXPECT_EQ(differences(*accel, frame, result, report), 0) << c.name << " given rays\n" << report;
    }
    for (const BeamOptions& config : configs) {
      const BeamResult result = rays->trace_beams(pixels_of(frame), config);
      std::string report;
      EXPECT_EQ(differences(*accel, frame, result, report), 0)
          << c.name << " tile " << config.tile_size << " frustum " << config.frustum << "\n" << report;
      const auto& s = result.stats;
      EXPECT_EQ(s.pixels_missed + s.pixels_one_primitive + s.pixels_in_front + s.pixels_traced, std::uint64_t(c.width) * std::uint64_t(c.height))
          << c.name;
      total += s;
    }
  }
  // Every way of resolving a pixel was taken somewhere, so the comparison above covered each of them.
  EXPECT_GT(total.pixels_missed, 0u);
  EXPECT_GT(total.pixels_one_primitive, 0u);
  EXPECT_GT(total.pixels_in_front, 0u);
  EXPECT_GT(total.pixels_traced, 0u);
  if (packets_run) {
    // Packets traced, and rays traced again for a possible tie (the edge grid's rays through shared edges).
    EXPECT_GT(total.pixels_in_packets, 0u);
    EXPECT_GT(total.pixels_retraced, 0u);
  }
}

INSTANTIATE_TEST_SUITE_P(Conformance, BeamIdentity, ::testing::ValuesIn(testing::generalized_specs()),
                         conformance::spec_test_name);

TEST(BeamIdentityShared, BunnyMatchesIntersect) {
  const auto file = testing::shared_scenes_dir() / "bunny.ply";
  RAYACCEL_NEED_SHARED_FILE(file);
  const Scene scene = load_scene(file.string());
  const Camera camera = standard_camera(file).value_or(Camera::framing(scene.bounds()));
  const CameraFrame frame = camera.frame(64, 64);
  for (const char* spec : {"bvh", "bvh_wide", "kdtree:builder=sah"}) {
    auto accel = make_accelerator(spec);
    accel->build(scene);
    const BeamResult result = generalized::make_generalized_rays(*accel, scene)->trace_beams(pixels_of(frame), {});
    std::string report;
    EXPECT_EQ(differences(*accel, frame, result, report), 0) << spec << "\n" << report;
  }
}

TEST(BeamTracer, EveryBvhVolumeHasBeamsAndCones) {
  // The registry's volume choices, not a list here: a new volume without beams fails this test.
  const auto& options = find_accelerator("bvh").options;
  const auto bv = std::find_if(options.begin(), options.end(), [](const OptionSpec& o) { return o.key == "bv"; });
  ASSERT_NE(bv, options.end());
  ASSERT_GE(bv->choices.size(), 8u);
  for (const std::string& volume : bv->choices) {
    EXPECT_TRUE(generalized::supports_generalized_rays(*make_accelerator("bvh:bv=" + volume))) << volume;
  }
}

TEST(BeamTracer, RejectsBadInput) {
  const Scene scene = edge_grid();
  auto accel = make_accelerator("bvh");
  accel->build(scene);
  const auto rays = generalized::make_generalized_rays(*accel, scene);
  const CameraFrame frame = Camera{}.frame(4, 4);
  EXPECT_THROW(rays->trace_beams(pixels_of(frame), BeamOptions{.tile_size = 0}), Error);
  EXPECT_THROW(rays->trace_beams(PixelRays{0, 4, pixels_of(frame).ray_at, {}}, {}), Error);
  const PixelRays moving{4, 4, [](float x, float y) { return Ray{{x, y, 1}, 0, {0, 0, -1}}; }, {}};
  EXPECT_THROW(rays->trace_beams(moving, {}), Error);
  // Rays given by the caller: one a pixel, sharing one origin; hits: one a pixel.
  std::vector<Ray> given(15, frame.ray(0, 0));
  PixelRays short_of_one = pixels_of(frame);
  short_of_one.rays = given;
  EXPECT_THROW(rays->trace_beams(short_of_one, {}), Error);
  given.push_back(frame.ray(1, 1));
  given[3].origin.x += 1.0f;
  PixelRays two_origins = pixels_of(frame);
  two_origins.rays = given;
  EXPECT_THROW(rays->trace_beams(two_origins, {}), Error);
  // bvh_wide's frustum beams check given rays' origins in their tiles, not before: the same error.
  auto wide = make_accelerator("bvh_wide");
  wide->build(scene);
  EXPECT_THROW(generalized::make_generalized_rays(*wide, scene)->trace_beams(two_origins, {}), Error);
  PixelRays one_origin = pixels_of(frame);
  given[3].origin = given[0].origin;
  one_origin.rays = given;
  EXPECT_NO_THROW(generalized::make_generalized_rays(*wide, scene)->trace_beams(one_origin, {}));
  std::vector<Hit> hits(15);
  EXPECT_THROW(rays->trace_beams(pixels_of(frame), {}, hits), Error);
  auto octree = make_accelerator("octree");
  octree->build(scene);
  EXPECT_FALSE(generalized::supports_generalized_rays(*octree));
  EXPECT_THROW(generalized::make_generalized_rays(*octree, scene), Error);
}

}  // namespace
}  // namespace rayaccel
