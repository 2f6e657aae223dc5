// Tests of the renderer (normals, ambient occlusion, heat map with legend), the colour ramp, the bitmap font and
// PNG output (read back with load_png()).
#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "rayaccel/accel/brute_force.h"
#include "rayaccel/core/error.h"
#include "rayaccel/render/bitmap_font.h"
#include "rayaccel/render/colormap.h"
#include "rayaccel/render/heatmap.h"
#include "rayaccel/render/image_compare.h"
#include "rayaccel/render/renderer.h"


namespace rayaccel {
namespace {

/// A square of two triangles, corner c and edges a, b, appended to `mesh`.
void add_quad(TriangleMesh& mesh, const Vec3& c, const Vec3& a, const Vec3& b) {
  const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), {c, c + a, c + a + b, c + b});
  mesh.triangles.push_back({base, base + 1, base + 2});
  mesh.triangles.push_back({base, base + 2, base + 3});
}

/// A tilted unit quad in the middle of the view of camera_for_quad(): geometry in the center, background at the
/// corners.
Scene tilted_quad() {
  TriangleMesh mesh;
  add_quad(mesh, {-0.5f, -0.5f, -0.2f}, {1.0f, 0.0f, 0.4f}, {0.0f, 1.0f, 0.0f});
  return Scene::from_mesh(std::move(mesh), "quad");
}

/// A floor (y = -0.5, normal -y) meeting a wall (z = -0.3) in a crease along x.
Scene crease_scene() {
  TriangleMesh mesh;
  add_quad(mesh, {-2.0f, -0.5f, -2.0f}, {4.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 4.0f});
  add_quad(mesh, {-2.0f, -0.5f, -0.3f}, {0.0f, 3.0f, 0.0f}, {4.0f, 0.0f, 0.0f});
  return Scene::from_mesh(std::move(mesh), "crease");
}

Camera camera_for_crease() {
  Camera cam;
  cam.eye = {0.0f, 1.0f, 3.0f};
  cam.at = {0.0f, -0.3f, 0.0f};
  cam.fov_degrees = 50.0f;
  return cam;
}

Camera camera_for_quad() {
  Camera cam;
  cam.eye = {0.0f, 0.0f, 3.0f};
  cam.at = {0.0f, 0.0f, 0.0f};
  cam.fov_degrees = 40.0f;
  return cam;
}

RenderResult render_with(const Scene& scene, ShadingMode mode, int width, int height, int ao_samples = 4,
                         std::optional<CostRange> heat_scale = {}) {
  BruteForce bf;
  bf.build(scene);
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.mode = mode;
  settings.ao_samples = ao_samples;
  settings.heat_scale = heat_scale;
  return render(bf, scene, camera_for_quad(), settings);
}

TEST(Renderer, NormalsImageHasTheRightSizeAndShowsGeometry) {
  const Scene scene = tilted_quad();
  const RenderResult r = render_with(scene, ShadingMode::normals, 48, 32);
  EXPECT_EQ(r.image.width, 48);
  EXPECT_EQ(r.image.height, 32);
  EXPECT_EQ(r.image.rgb.size(), 48u * 32u * 3u);
  EXPECT_EQ(r.rays, 48u * 32u);
  // Every primary ray tests both triangles and enters one "node".
  EXPECT_EQ(r.total.primitives_tested, 2u * 48u * 32u);
  EXPECT_EQ(r.total.nodes_visited, 48u * 32u);
  const Rgb center = r.image.at(24, 16), corner = r.image.at(0, 0);
  EXPECT_NE(center, corner);
  // |n| of the quad's normal (0.4, 0, -1)/|.| as colour: blue dominant, some red, no green.
  const Vec3 n = normalize(Vec3{-0.4f, 0.0f, 1.0f});
  EXPECT_NEAR(center.r, n.x * -255.0f, 1.0f);
  EXPECT_EQ(center.g, 0);
  EXPECT_NEAR(center.b, n.z * 255.0f, 1.0f);
}

TEST(Renderer, HeatMapDiffersBetweenGeometryAndBackgroundAndHasALegend) {
  const Scene scene = tilted_quad();
  const int w = 96, h = 96;
  const RenderResult r = render_with(scene, ShadingMode::heatmap, w, h);
  const int legend_top = h - heat_legend_height(w, h);
  ASSERT_GT(legend_top, h / 2);
  // Brute force costs the same for every ray (3 = 1 node + 2 primitives): the scale is the single value 3, every
  // pixel takes the middle of the ramp, and hits are shaded by the surface angle.
  const Rgb mid = heat_colour(0.5f);
  EXPECT_EQ(r.image.at(1, 1), mid);
  EXPECT_NE(r.image.at(w / 2, h / 2 - 10), mid);
  EXPECT_LT(r.image.at(w / 2, h / 2 - 10).r, mid.r);
  // The colour bar runs from heat_colour(0) at its left end to heat_colour(1) at its right end.
  const int bar_y = legend_top + 3 + 4;  // scale 1: margin 3, bar height 8
  EXPECT_EQ(r.image.at(3, bar_y), heat_colour(0.0f));
  EXPECT_EQ(r.image.at(w - 4, bar_y), heat_colour(1.0f));
  // The labels are white text on the panel under the bar.
  int white = 0;
  for (int y = legend_top; y < h; ++y) {
    for (int x = 0; x < w; ++x) white += r.image.at(x, y) == Rgb{240, 240, 240} ? 1 : 0;
  }
  EXPECT_GT(white, 20);
}

TEST(Renderer, HeatMapScaleRunsFromMinToThe99thPercentile) {
  // Brute force costs the same for every ray, so the scale is checked on synthetic statistics.
  std::vector<TraversalStats> stats(201);
  for (std::size_t i = 0; i < stats.size(); ++i) stats[i] = {1, 2 * i};  // costs 1, 3, ..., 401
  stats[17].primitives_tested = 100000;                                 // one outlier
  const CostRange range = cost_range(stats);
  EXPECT_EQ(range.min, 1u);
  EXPECT_EQ(range.highest, 100001u);
  // Sorted costs: 1, 3, ..., 33, 37, ..., 401, 100001; position floor(0.99 * 200) = 198 holds 399.
  EXPECT_EQ(range.max, 399u);
  EXPECT_EQ(cost_fraction(1, range), 0.0f);
  EXPECT_EQ(cost_fraction(399, range), 1.0f);
  EXPECT_EQ(cost_fraction(100001, range), 1.0f);
  EXPECT_FLOAT_EQ(cost_fraction(200, range), 0.5f);
  EXPECT_EQ(cost_fraction(7, CostRange{7, 7, 7}), 0.5f);
  const CostRange empty = cost_range(std::span<const TraversalStats>{});
  EXPECT_EQ(empty.min, 0u);
  EXPECT_EQ(empty.highest, 0u);
}

TEST(Renderer, HeatMapIsItsFrameDrawnOnItsOwnScale) {
  const Scene scene = tilted_quad();
  const RenderResult r = render_with(scene, ShadingMode::heatmap, 96, 80);
  ASSERT_EQ(r.heat.cost.size(), std::size_t{96 * 80});
  EXPECT_EQ(r.heat.range.min, 3u);  // brute force: 1 node + 2 primitives per ray
  EXPECT_EQ(r.heat.range.highest, 3u);
  EXPECT_EQ(draw_heat_frame(r.heat, r.heat.range).rgb, r.image.rgb);
  // Misses keep the plain ramp; hits are darkened by how obliquely the ray meets the quad.
  EXPECT_EQ(r.heat.brightness[0], 1.0f);
  const std::size_t center = 40 * 96 + 48;
  EXPECT_GE(r.heat.brightness[center], 0.6f);
  EXPECT_LT(r.heat.brightness[center], 0.9f);
  // Other modes keep no frame.
  EXPECT_TRUE(render_with(scene, ShadingMode::normals, 8, 8).heat.cost.empty());
}

TEST(Renderer, FixedHeatScalePlacesEveryCostOnIt) {
  const RenderResult r = render_with(tilted_quad(), ShadingMode::heatmap, 64, 64, 4, CostRange{0, 12, 12});
  // Every ray costs 3, a quarter of the way up a scale from 0 to 12: a miss pixel shows heat_colour(0.25).
  EXPECT_EQ(r.image.at(1, 1), heat_colour(0.25f));
  EXPECT_NE(r.image.at(1, 1), heat_colour(0.5f));
  EXPECT_EQ(draw_heat_frame(r.heat, CostRange{0, 12, 12}).rgb, r.image.rgb);
}

TEST(Renderer, SharedHeatScalePoolsThePixelsOfEveryFrame) {
  HeatFrame cheap, dear;
  for (HeatFrame* f : {&cheap, &dear}) {
    f->width = 10;
    f->height = 10;
    f->brightness.assign(100, 1.0f);
  }
  for (std::uint64_t i = 0; i < 100; ++i) {
    cheap.cost.push_back(i);        // 0 .. 99
    dear.cost.push_back(100 + i);   // 100 .. 199
  }
  dear.cost[5] = 100000;  // one outlier
  cheap.range = cost_range(cheap.cost);
  dear.range = cost_range(dear.cost);
  const std::vector<const HeatFrame*> frames = {&cheap, &dear};
  const CostRange shared = shared_cost_range(frames);
  EXPECT_EQ(shared.min, 0u);
  EXPECT_EQ(shared.highest, 100000u);
  // Pooled sorted costs 0 .. 104, 106 .. 199, 100000: position floor(0.99 * 199) = 197 holds 198.
  EXPECT_EQ(shared.max, 198u);
  // Equal costs get equal colours in both images; each image's own scale would colour them differently.
  cheap.cost[0] = 150;
  const Image a = draw_heat_frame(cheap, shared), b = draw_heat_frame(dear, shared);
  EXPECT_EQ(a.at(0, 0), b.at(0, 5));  // dear.cost[50] = 150
  EXPECT_NE(draw_heat_frame(cheap, cheap.range).at(0, 0), draw_heat_frame(dear, dear.range).at(0, 5));
  EXPECT_EQ(shared_cost_range(std::vector<const HeatFrame*>{}).max, 0u);
  HeatFrame broken = cheap;
  broken.brightness.pop_back();
  EXPECT_THROW(draw_heat_frame(broken, shared), Error);
}

TEST(Renderer, ClippedLegendSaysSo) {
  Image plain = Image::filled(400, 200, {0, 0, 0});
  Image clipped = plain;
  draw_heat_legend(plain, {12, 345, 345});
  draw_heat_legend(clipped, {12, 345, 9999});
  const int top = 200 - heat_legend_height(400, 200);
  int differing = 0;
  for (int y = top; y < 200; ++y) {
    for (int x = 0; x < 400; ++x) differing += plain.at(x, y) != clipped.at(x, y) ? 1 : 0;
  }
  EXPECT_GT(differing, 20);
}

TEST(Renderer, LegendLabelsShowTheRange) {
  Image a = Image::filled(200, 120, {0, 0, 0});
  Image b = a;
  draw_heat_legend(a, {12, 3456});
  draw_heat_legend(b, {12, 9999});
  const int top = 120 - heat_legend_height(200, 120);
  // Left labels agree, right labels differ; nothing above the panel changes.
  bool left_same = true, right_differs = false;
  for (int y = top; y < 120; ++y) {
    for (int x = 0; x < 60; ++x) left_same = left_same && a.at(x, y) == b.at(x, y);
    for (int x = 140; x < 200; ++x) right_differs = right_differs || a.at(x, y) != b.at(x, y);
  }
  EXPECT_TRUE(left_same);
  EXPECT_TRUE(right_differs);
  for (int y = 0; y < top; ++y) EXPECT_EQ(a.at(100, y), (Rgb{0, 0, 0}));
}

TEST(Renderer, AmbientOcclusionOfAnOpenPlaneIsUnoccludedEverywhere) {
  // Nothing but the plane: any occluded AO ray would be a self-intersection.
  const Scene scene = tilted_quad();
  const RenderResult r = render_with(scene, ShadingMode::ambient_occlusion, 40, 40, 16);
  const std::uint8_t open = encode_srgb(0.8);
  int hits = 0;
  for (int y = 0; y < 40; ++y) {
    for (int x = 0; x < 40; ++x) {
      const Rgb c = r.image.at(x, y);
      if (c == Rgb{open, open, open}) ++hits;
    }
  }
  EXPECT_GT(hits, 200);
  EXPECT_GT(r.rays, 40u * 40u + 200u * 16u);
}

TEST(Renderer, AmbientOcclusionDarkensACreaseAndIsThreadCountIndependent) {
  const Scene scene = crease_scene();
  BruteForce bf;
  bf.build(scene);
  RenderSettings settings;
  settings.width = settings.height = 48;
  settings.mode = ShadingMode::ambient_occlusion;
  settings.ao_samples = 32;
  settings.ao_distance_fraction = 0.2f;
  const Camera cam = camera_for_crease();
  RenderResult single;
  tbb::task_arena arena(1);
  arena.execute([&] { single = render(bf, scene, cam, settings); });
  const RenderResult many = render(bf, scene, cam, settings);
  EXPECT_EQ(single.image.rgb, many.image.rgb);
  EXPECT_EQ(single.rays, many.rays);
  // Average brightness of hit pixels next to the crease (the wall's foot) against those far from it.
  BruteForce probe;
  probe.build(scene);
  double near_sum = 0, far_sum = 0;
  int near_n = 0, far_n = 0;
  const CameraFrame f = cam.frame(48, 48);
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 48; ++x) {
      const Ray ray = f.ray(x, y);
      const Hit hit = probe.intersect(ray);
      if (!hit.found()) continue;
      const Vec3 p = ray.origin + ray.direction * hit.t;
      const double distance_to_crease = std::hypot(p.y + 0.5f, p.z + 0.3f);
      const double grey = many.image.at(x, y).r;
      if (distance_to_crease < 0.15) near_sum += grey, ++near_n;
      if (distance_to_crease > 1.2) far_sum += grey, ++far_n;
    }
  }
  ASSERT_GT(near_n, 5);
  ASSERT_GT(far_n, 5);
  EXPECT_LT(near_sum / near_n, far_sum / far_n - 20.0);
}

TEST(Renderer, AdaptiveAmbientOcclusionSpendsRaysOnlyWhereTheEstimateIsUncertain) {
  const Scene crease = crease_scene();
  const Scene open_plane = tilted_quad();
  RenderSettings settings;
  settings.width = settings.height = 32;
  settings.mode = ShadingMode::ambient_occlusion;
  settings.ao_samples = 8;
  settings.ao_distance_fraction = 0.2f;
  const Camera cam = camera_for_crease();
  const auto run = [&](const Scene& scene, int max_samples, const Camera& camera) {
    BruteForce bf;
    bf.build(scene);
    RenderSettings s = settings;
    s.ao_max_samples = max_samples;
    return render(bf, scene, camera, s);
  };
  // Nothing occludes an open plane: every estimate is certain after the first round, so adaptive sampling adds
  // nothing and gives the fixed image.
  const RenderResult fixed_open = run(open_plane, 0, camera_for_quad());
  const RenderResult adaptive_open = run(open_plane, 64, camera_for_quad());
  EXPECT_EQ(adaptive_open.rays, fixed_open.rays);
  EXPECT_EQ(adaptive_open.image.rgb, fixed_open.image.rgb);
  // Beside a crease some estimates are uncertain: they get more rays, far fewer than 64 for every hit.
  const RenderResult fixed = run(crease, 0, cam), adaptive = run(crease, 64, cam), all = run(crease, 64, cam);
  EXPECT_GT(adaptive.rays, fixed.rays);
  EXPECT_EQ(adaptive.rays, all.rays);  // deterministic
  std::uint64_t hits = 0;
  {
    BruteForce bf;
    bf.build(crease);
    const CameraFrame f = cam.frame(32, 32);
    for (int y = 0; y < 32; ++y) {
      for (int x = 0; x < 32; ++x) hits += bf.intersect(f.ray(x, y)).found() ? 1 : 0;
    }
  }
  EXPECT_LT(adaptive.rays, hits + hits * 32) << "uncertain hits only";
  RenderSettings bad = settings;
  bad.ao_max_samples = 4;
  BruteForce bf;
  bf.build(crease);
  EXPECT_THROW(render(bf, crease, cam, bad), Error);
}

TEST(Renderer, ProgressRisesToOne) {
  const Scene scene = tilted_quad();
  BruteForce bf;
  bf.build(scene);
  RenderSettings settings;
  settings.width = 1024;  // 32 rows per chunk
  settings.height = 100;
  std::vector<float> reported;
  settings.progress = [&](float f) { reported.push_back(f); };
  render(bf, scene, camera_for_quad(), settings);
  ASSERT_GE(reported.size(), 2u);
  for (std::size_t i = 1; i < reported.size(); ++i) EXPECT_GT(reported[i], reported[i - 1]);
  EXPECT_EQ(reported.back(), 1.0f);
}

TEST(Renderer, BadSettingsAreErrors) {
  const Scene scene = tilted_quad();
  BruteForce bf;
  bf.build(scene);
  RenderSettings settings;
  settings.width = 0;
  EXPECT_THROW(render(bf, scene, camera_for_quad(), settings), Error);
  settings.width = 8;
  settings.mode = ShadingMode::ambient_occlusion;
  settings.ao_samples = 0;
  EXPECT_THROW(render(bf, scene, camera_for_quad(), settings), Error);
  EXPECT_EQ(parse_shading_mode("normals"), ShadingMode::normals);
  EXPECT_EQ(parse_shading_mode("ao"), ShadingMode::ambient_occlusion);
  EXPECT_EQ(parse_shading_mode("heatmap"), ShadingMode::heatmap);
  try {
    parse_shading_mode("phong");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("phong"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("heatmap"), std::string::npos);
  }
}

TEST(Renderer, EmptySceneRendersBackground) {
  const Scene scene = Scene::from_mesh({}, "empty");
  for (const ShadingMode mode : {ShadingMode::normals, ShadingMode::ambient_occlusion, ShadingMode::heatmap}) {
    const RenderResult r = render_with(scene, mode, 16, 16);
    EXPECT_EQ(r.image.at(8, 2), r.image.at(2, 3));
  }
}

TEST(Renderer, PngRoundTrip) {
  const Scene scene = tilted_quad();
  const RenderResult r = render_with(scene, ShadingMode::heatmap, 64, 40);
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "rayaccel_render_test.png";
  r.image.save_png(path);
  const Image back = load_png(path);
  EXPECT_EQ(back.width, 64);
  EXPECT_EQ(back.height, 40);
  EXPECT_EQ(back.rgb, r.image.rgb);
  std::filesystem::remove(path);

  const std::filesystem::path bad = std::filesystem::temp_directory_path() / "rayaccel_no_such_dir" / "x.png";
  try {
    r.image.save_png(bad);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos);
  }
  EXPECT_THROW(Image{}.save_png(path), Error);
}

TEST(Colormap, LightnessRisesMonotonically) {
  // Relative luminance (Rec. 709 weights on linearized sRGB) must rise along the ramp.
  auto luminance = [](Rgb c) {
    auto lin = [](std::uint8_t v) {
      const double s = v / 255.0;
      return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
    };
    return 0.2126 * lin(c.r) + 0.7152 * lin(c.g) + 0.0722 * lin(c.b);
  };
  double previous = -1.0;
  for (int i = 0; i <= 32; ++i) {
    const double y = luminance(heat_colour(static_cast<float>(i) / 32.0f));
    EXPECT_GT(y, previous) << "step " << i;
    previous = y;
  }
  EXPECT_LT(luminance(heat_colour(0.0f)), 0.02);
  EXPECT_GT(luminance(heat_colour(1.0f)), 0.8);
  EXPECT_EQ(heat_colour(std::nanf("")), heat_colour(0.0f));
  EXPECT_EQ(heat_colour(7.0f), heat_colour(1.0f));
}

TEST(BitmapFont, DrawsInkInsideTheTextBox) {
  EXPECT_EQ(text_width("", 2), 0);
  EXPECT_EQ(text_width("123", 1), 17);
  EXPECT_EQ(text_width("123", 2), 34);
  for (char c : std::string("0123456789COSTNDEPRIMAXY+-.")) EXPECT_TRUE(has_glyph(c)) << c;
  EXPECT_FALSE(has_glyph('#'));
  Image image = Image::filled(40, 20, {0, 0, 0});
  draw_text(image, "80", 3, 4, 2, {255, 255, 255});
  int ink = 0;
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 40; ++x) {
      const bool inside = x >= 3 && x < 3 + text_width("80", 2) && y >= 4 && y < 4 + 14;
      if (image.at(x, y).r == 255) {
        ++ink;
        EXPECT_TRUE(inside) << x << "," << y;
      }
    }
  }
  EXPECT_GT(ink, 40);
  draw_text(image, "999", 35, 15, 3, {1, 2, 3});  // clipped at the edges, no crash
}

}  // namespace
}  // namespace rayaccel
