// Tests of the recursive renderer and of the ways it traces fewer rays: adaptive sampling (threshold 0 equals
// uniform sampling at its finest level; agreeing corners are never subdivided), adaptive tree depth (a weight
// threshold equals the fixed depth it implies), any-hit shadow rays (same image as closest-hit ones), and the image
// error measures.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/render/image_compare.h"
#include "rayaccel/render/image_sampler.h"
#include "rayaccel/render/whitted.h"
#include "rayaccel/scene/builtin_scenes.h"

namespace rayaccel {
namespace {

struct WhittedSetup {
  Scene scene;
  std::unique_ptr<Accelerator> accel;
  Camera camera;
  SceneMaterials materials;
  std::vector<Light> lights;
};

WhittedSetup setup(const std::string& name, const std::map<std::string, std::string>& params, const std::string& spec) {
  WhittedSetup s{make_builtin_scene(name, params), make_accelerator(spec), {}, {}, {}};
  s.accel->build(s.scene);
  s.camera = Camera::framing(s.scene.bounds());
  if (name == "glass") {
    s.camera.eye = {0.0f, 2.5f, 5.0f};
    s.camera.at = {0.0f, 0.8f, 0.0f};
  }
  s.materials = default_materials(s.scene);
  s.lights = default_lights(s.scene.bounds(), s.camera, 2);
  return s;
}

WhittedResult render(const WhittedSetup& s, const WhittedSettings& settings, const AntiAliasing& aa, int w = 32, int h = 24) {
  return render_whitted(*s.accel, s.scene, s.camera, w, h, s.materials, s.lights, settings, aa);
}

AntiAliasing adaptive(float threshold, int max_level) {
  AntiAliasing aa;
  aa.mode = AntiAliasing::Mode::adaptive;
  aa.threshold = threshold;
  aa.max_level = max_level;
  return aa;
}

AntiAliasing uniform(int n) {
  AntiAliasing aa;
  aa.n = n;
  return aa;
}

TEST(Whitted, AdaptiveSamplingWithThresholdZeroEqualsUniformAtItsFinestLevel) {
  const WhittedSetup s = setup("glass", {{"level", "2"}}, "bvh_wide");
  const WhittedResult a = render(s, {}, adaptive(0.0f, 2));
  const WhittedResult u = render(s, {}, uniform(4));
  ASSERT_EQ(a.samples.pixels.size(), u.samples.pixels.size());
  // The same samples (same points, same random streams), filtered in a different order: equal up to rounding.
  for (std::size_t i = 0; i < a.samples.pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(a.samples.pixels[i][c], u.samples.pixels[i][c], 1e-5f) << "pixel " << i;
    }
    EXPECT_EQ(a.samples.samples[i], u.samples.samples[i]) << "pixel " << i;
  }
  EXPECT_EQ(a.samples.sample_count, u.samples.sample_count);
  // Every point of the image's fine grid once: (4 w + 1) (4 h + 1) for 32 x 24 pixels, 16 rays per pixel and a border
  // (it was 33 * 25 + 32 * 24 * 21, 22 per pixel, while points on an edge between two pixels were traced by both).
  EXPECT_EQ(a.samples.sample_count, std::uint64_t{129 * 97});
  EXPECT_EQ(a.counts.camera, a.samples.sample_count);
  EXPECT_EQ(a.counts.camera, u.counts.camera);
}

TEST(Whitted, AgreeingCornersAreNeverSubdivided) {
  const AntiAliasing aa = adaptive(0.1f, 3);
  // A constant image: only the shared pixel corners are traced.
  const SampledImage flat = sample_image(10, 7, aa, [](float, float, std::uint64_t) { return Vec3{0.3f, 0.2f, 0.1f}; });
  EXPECT_EQ(flat.sample_count, 11u * 8u);
  for (const std::uint32_t n : flat.samples) EXPECT_EQ(n, 4u);
  // A sharp vertical edge at x = 4.3: only the pixels it crosses are subdivided, down to the finest level.
  const SampledImage edge =
      sample_image(10, 7, aa, [](float x, float, std::uint64_t) { return x < 4.3f ? Vec3{1.0f} : Vec3{0.0f}; });
  for (int y = 0; y < 7; ++y) {
    for (int x = 0; x < 10; ++x) {
      const std::uint32_t n = edge.samples[static_cast<std::size_t>(y) * 10 + x];
      if (x == 4) {
        EXPECT_GT(n, 4u) << x << "," << y;
        EXPECT_NEAR(edge.pixels[static_cast<std::size_t>(y) * 10 + x].x, 0.3f, 0.07f);  // coverage of the pixel
      } else {
        EXPECT_EQ(n, 4u) << x << "," << y;
      }
    }
  }
}

TEST(Whitted, WeightThresholdEqualsTheFixedDepthItImplies) {
  // Every sphereflake surface is a 0.6 mirror: the k-th bounce carries weight 0.6^k, so a threshold between 0.6^4
  // and 0.6^3 stops the tree after three bounces, exactly as max_depth = 3 does.
  const WhittedSetup s = setup("sphereflake", {{"level", "2"}}, "bvh_wide");
  ASSERT_EQ(s.materials.table.size(), 1u);
  ASSERT_FLOAT_EQ(s.materials.table[0].mirror, 0.6f);
  WhittedSettings by_weight;
  by_weight.max_depth = 12;
  by_weight.min_weight = 0.2f;
  WhittedSettings by_depth;
  by_depth.max_depth = 3;
  const WhittedResult a = render(s, by_weight, uniform(1)), b = render(s, by_depth, uniform(1));
  EXPECT_EQ(a.image.rgb, b.image.rgb);
  EXPECT_EQ(a.counts.reflection, b.counts.reflection);
  EXPECT_EQ(a.counts.shadow, b.counts.shadow);
  // Weight 0 is fixed-depth recursion: it traces the deeper bounces the threshold saved.
  WhittedSettings fixed = by_weight;
  fixed.min_weight = 0.0f;
  const WhittedResult c = render(s, fixed, uniform(1));
  EXPECT_GT(c.counts.reflection, a.counts.reflection);
  EXPECT_GT(c.counts.nodes_visited, a.counts.nodes_visited);
}

TEST(Whitted, AnyHitAndClosestHitShadowRaysGiveTheSameImage) {
  for (const char* name : {"glass", "sphereflake"}) {
    const WhittedSetup s = setup(name, {{"level", "2"}}, "bvh_wide");
    WhittedSettings any, closest;
    closest.any_hit_shadows = false;
    const WhittedResult a = render(s, any, uniform(1)), c = render(s, closest, uniform(1));
    EXPECT_EQ(a.image.rgb, c.image.rgb) << name;
    EXPECT_EQ(a.counts.shadow, c.counts.shadow) << name;
    EXPECT_GT(a.counts.shadow, 0u) << name;
    // Node visits are not compared: bvh_wide's any-hit traversal takes children in lane order, its closest-hit
    // traversal nearest first, so on short shadow rays either may visit fewer nodes (the renderer reports both).
  }
}

TEST(Whitted, GlassRefractsAndEveryStructureDrivesIt) {
  const WhittedSetup reference = setup("glass", {{"level", "2"}}, "brute_force");
  const WhittedResult want = render(reference, {}, uniform(1));
  EXPECT_GT(want.counts.refraction, 0u);
  EXPECT_GT(want.counts.reflection, 0u);
  for (const char* spec : {"bvh_wide", "bvh", "bvh:bv=obb", "kdtree:builder=sah", "grid", "octree", "bsp"}) {
    const WhittedSetup s = setup("glass", {{"level", "2"}}, spec);
    const WhittedResult got = render(s, {}, uniform(1));
    std::size_t differing = 0;
    for (std::size_t i = 0; i < got.image.rgb.size(); i += 3) {
      differing += got.image.rgb[i] != want.image.rgb[i] || got.image.rgb[i + 1] != want.image.rgb[i + 1] ||
                   got.image.rgb[i + 2] != want.image.rgb[i + 2];
    }
    // Structures agree with brute force except where a ray meets a shared edge (a tie in t may name the other
    // triangle, whose normal differs): a handful of pixels at most.
    EXPECT_LE(differing, 8u) << spec;
  }
}

TEST(Whitted, BadSettingsAreErrors) {
  const WhittedSetup s = setup("glass", {{"level", "1"}}, "bvh_wide");
  WhittedSettings bad;
  bad.max_depth = -1;
  EXPECT_THROW(render(s, bad, uniform(1)), Error);
  bad = {};
  bad.min_weight = 2.0f;
  EXPECT_THROW(render(s, bad, uniform(1)), Error);
  SceneMaterials wrong = s.materials;
  wrong.prim_material.pop_back();
  EXPECT_THROW(render_whitted(*s.accel, s.scene, s.camera, 4, 4, wrong, s.lights, {}, uniform(1)), Error);
  EXPECT_THROW(default_materials(make_builtin_scene("sphere", {{"level", "1"}}), MaterialOptions{1.5f}), Error);
  EXPECT_THROW(default_lights(s.scene.bounds(), s.camera, 0), Error);
}

TEST(AntiAliasingSpec, ParsesAndRejects) {
  EXPECT_EQ(parse_anti_aliasing("uniform:n=8").n, 8);
  const AntiAliasing a = parse_anti_aliasing("adaptive:threshold=0.25,max_level=3");
  EXPECT_EQ(a.mode, AntiAliasing::Mode::adaptive);
  EXPECT_FLOAT_EQ(a.threshold, 0.25f);
  EXPECT_EQ(a.max_level, 3);
  EXPECT_EQ(finest_subdivision(a), 8);
  for (const char* bad : {"uniform:n=3", "uniform:n=128", "uniform:n=x", "adaptive:threshold=2", "adaptive:max_level=7",
                          "adaptive:max_level=1.5", "adaptive:n=2", "jittered", "uniform:threshold=0.1"}) {
    EXPECT_THROW(parse_anti_aliasing(bad), Error) << bad;
  }
  const Vec3 same[2] = {Vec3{0.5f}, Vec3{0.5f}};
  EXPECT_EQ(contrast(same, 2), 0.0f);
  const Vec3 apart[2] = {Vec3{1.0f, 0.0f, 0.0f}, Vec3{0.0f, 0.0f, 0.0f}};
  EXPECT_FLOAT_EQ(contrast(apart, 2), 1.0f);
}

TEST(ImageCompare, RmseAndPsnr) {
  Image a = Image::filled(4, 2, {10, 20, 30});
  EXPECT_EQ(compare_images(a, a).rmse, 0.0);
  EXPECT_TRUE(std::isinf(compare_images(a, a).psnr));
  Image b = a;
  b.set(0, 0, {13, 24, 30});  // squared differences 9 + 16 over 24 channels
  EXPECT_NEAR(compare_images(b, a).rmse, std::sqrt(25.0 / 24.0), 1e-12);
  EXPECT_NEAR(compare_images(b, a).psnr, 20.0 * std::log10(255.0 / std::sqrt(25.0 / 24.0)), 1e-9);
  EXPECT_THROW(compare_images(a, Image::filled(2, 2, {})), Error);
  const auto path = std::filesystem::temp_directory_path() / "rayaccel_whitted_roundtrip.png";
  b.save_png(path);
  EXPECT_EQ(load_png(path).rgb, b.rgb);
  std::filesystem::remove(path);
  try {
    load_png(path);
    FAIL() << "no error for a missing file";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos);
  }
}

}  // namespace
}  // namespace rayaccel
