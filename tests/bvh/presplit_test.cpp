// Triangle pre-splitting (bvh/presplit.h): piece boxes inside the triangle's box and together covering the triangle,
// the reference budget, no-ops (budget 0, empty scenes, spheres, user primitives), degenerate input; and the wide BVH
// built over pre-split references: validate(), brute-force agreement, option errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "bvh_test_scenes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/bvh/presplit.h"
#include "rayaccel/core/error.h"
#include "rayaccel/geometry/clip_polygon.h"
#include "rayaccel/scene/builtin_scenes.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel {
namespace {

/// Large triangles spanning the scene in every direction (long diagonal slivers and big tilted triangles) among small
/// ones: the inputs pre-splitting is for. Vertices are multiples of 1/8 in [0, 16], so every point sampled at
/// barycentric multiples of 1/16 below is an exact float.
Scene diagonal_scene(std::uint32_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> coord(0, 128), small(-4, 4);
  TriangleMesh mesh;
  for (std::uint32_t i = 0; i < count; ++i) {
    const Vec3 a{coord(rng) / 8.0f, coord(rng) / 8.0f, coord(rng) / 8.0f};
    Vec3 b, c;
    if (i % 3 == 0) {  // small
      b = a + Vec3{small(rng) / 8.0f, small(rng) / 8.0f, small(rng) / 8.0f};
      c = a + Vec3{small(rng) / 8.0f, small(rng) / 8.0f, small(rng) / 8.0f};
    } else {  // large or sliver
      b = {coord(rng) / 8.0f, coord(rng) / 8.0f, coord(rng) / 8.0f};
      c = i % 3 == 1 ? b + Vec3{0.125f, 0.0f, 0.125f} : Vec3{coord(rng) / 8.0f, coord(rng) / 8.0f, coord(rng) / 8.0f};
    }
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), {a, b, c});
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return Scene::from_mesh(std::move(mesh), "diagonal");
}

/// Checks the pieces of every triangle: same id as a valid primitive, box non-empty and inside the triangle's box,
/// every triangle has at least one piece, at most n + floor(fraction * n) references, and sample points of each
/// triangle (vertices, edge and interior points at barycentric multiples of 1/steps) each inside some piece box,
/// exactly when `exact_points`, else within the clipping margin. Returns the number of split triangles seen.
std::uint32_t check_pieces(const Scene& scene, const PresplitResult& result, float fraction, bool exact_points,
                           int steps = 16) {
  const std::size_t n = scene.valid_count();
  EXPECT_LE(result.refs.size(), n + static_cast<std::size_t>(std::floor(double(fraction) * double(n))));
  std::map<std::uint32_t, std::vector<AABB>> pieces;
  for (const PrimRef& ref : result.refs) {
    EXPECT_LT(ref.prim_id, scene.primitive_count());
    if (ref.prim_id >= scene.primitive_count()) continue;
    EXPECT_TRUE(scene.is_valid(ref.prim_id)) << "piece of invalid primitive " << ref.prim_id;
    EXPECT_FALSE(ref.bounds.is_empty()) << "empty piece of triangle " << ref.prim_id;
    EXPECT_TRUE(scene.primitive_bounds(ref.prim_id).contains(ref.bounds))
        << "piece of triangle " << ref.prim_id << " outside the triangle's box";
    pieces[ref.prim_id].push_back(ref.bounds);
  }
  EXPECT_EQ(pieces.size(), n) << "every valid triangle keeps at least one reference";
  std::uint32_t split = 0, uncovered = 0;
  for (const auto& [id, boxes] : pieces) {
    if (boxes.size() > 1) ++split;
    const auto& t = scene.triangle(id);
    for (int i = 0; i <= steps; ++i) {
      for (int j = 0; i + j <= steps; ++j) {
        const double u = double(i) / steps, v = double(j) / steps;
        Vec3 p;
        for (int a = 0; a < 3; ++a) {
          p[a] = static_cast<float>(double(t[0][a]) + u * (double(t[1][a]) - t[0][a]) +
                                    v * (double(t[2][a]) - t[0][a]));
        }
        const bool covered = std::any_of(boxes.begin(), boxes.end(), [&](const AABB& box) {
          return (exact_points ? box : widen_for_clipping(box)).contains(p);
        });
        if (!covered && uncovered++ < 5) {
          ADD_FAILURE() << "point (" << p.x << ", " << p.y << ", " << p.z << ") of triangle " << id << " (" << i << "/"
                        << steps << ", " << j << "/" << steps << ") is in none of its " << boxes.size() << " pieces";
        }
      }
    }
  }
  EXPECT_EQ(split, result.split_triangles);
  return split;
}

TEST(Presplit, PiecesInsideTriangleBoxAndCoverTriangle) {
  const Scene scene = diagonal_scene(600, 5);
  for (float fraction : {0.1f, 0.3f, 1.0f, 4.0f}) {
    SCOPED_TRACE(fraction);
    const PresplitResult result = presplit_references(scene, {.fraction = fraction});
    EXPECT_GT(check_pieces(scene, result, fraction, true), 0u);
    // Most of the budget is used on a scene full of large diagonal triangles.
    EXPECT_GE(result.refs.size(), scene.valid_count() + std::size_t(0.5 * fraction * scene.valid_count()));
  }
}

TEST(Presplit, RandomSoupAndSliversWithinMargin) {
  const Scene soup = bvh_test::random_soup(2000, 7, 0.4f);
  check_pieces(soup, presplit_references(soup, {.fraction = 0.5f}), 0.5f, false, 8);
  const Scene slivers = make_builtin_scene("slivers", {{"count", "2000"}});
  EXPECT_GT(check_pieces(slivers, presplit_references(slivers, {.fraction = 0.3f}), 0.3f, false, 8), 0u);
}

TEST(Presplit, ZeroBudgetIsNoOp) {
  const Scene scene = diagonal_scene(300, 9);
  for (float fraction : {0.0f, -1.0f, 0.001f}) {  // 0.001 * 300 rounds down to no extra reference
    const PresplitResult result = presplit_references(scene, {.fraction = fraction});
    const PrimRefs plain = scene.build_references();
    ASSERT_EQ(result.refs.size(), plain.size());
    for (std::size_t i = 0; i < plain.size(); ++i) {
      EXPECT_EQ(result.refs[i].prim_id, plain[i].prim_id);
      EXPECT_EQ(result.refs[i].bounds, plain[i].bounds);
    }
    EXPECT_EQ(result.split_triangles, 0u);
  }
}

TEST(Presplit, EmptyAndTinyScenes) {
  EXPECT_TRUE(presplit_references(Scene::from_mesh({}), {.fraction = 1.0f}).refs.empty());
  EXPECT_TRUE(presplit_references(Scene{}, {.fraction = 1.0f}).refs.empty());
  // One triangle: the scene box is its box, the grid's middle planes cross it.
  TriangleMesh one;
  one.vertices = {{0, 0, 0}, {4, 1, 2}, {1, 4, 3}};
  one.triangles = {{0, 1, 2}};
  const Scene single = Scene::from_mesh(one);
  EXPECT_EQ(presplit_references(single, {.fraction = 0.3f}).refs.size(), 1u);  // floor(0.3) = 0 extra
  const PresplitResult split = presplit_references(single, {.fraction = 4.0f});
  EXPECT_EQ(check_pieces(single, split, 4.0f, true), 1u);
  EXPECT_GT(split.refs.size(), 1u);
}

TEST(Presplit, DegenerateInput) {
  // Invalid (NaN) and zero-area triangles are left out; flat scenes (one axis of zero extent) and identical
  // triangles still work.
  TriangleMesh mesh;
  const float nan = std::nanf("");
  mesh.vertices = {{0, 0, 0}, {8, 0, 8}, {0, 0, 8}, {nan, 0, 0}, {4, 0, 4}, {2, 0, 2}, {8, 0, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 4, 1}, {0, 5, 4}, {0, 6, 1}, {0, 1, 2}, {0, 6, 1}, {2, 2, 2}};
  const Scene flat = Scene::from_mesh(mesh);
  ASSERT_EQ(flat.valid_count(), 4u);
  check_pieces(flat, presplit_references(flat, {.fraction = 4.0f}), 4.0f, true);
  // Identical copies of one triangle.
  TriangleMesh copies;
  copies.vertices = {{0, 0, 0}, {1, 1, 1}, {1, 0, 0}};
  for (int i = 0; i < 100; ++i) copies.triangles.push_back({0, 1, 2});
  const Scene same = Scene::from_mesh(copies);
  check_pieces(same, presplit_references(same, {.fraction = 1.0f}), 1.0f, true);
  // Tiny triangles far from the origin: box widths near float precision.
  TriangleMesh far;
  for (std::uint32_t i = 0; i < 50; ++i) {
    const float x = 1.0e6f + static_cast<float>(i) * 0.0625f;
    far.vertices.insert(far.vertices.end(), {{x, 1.0e6f, 0}, {x + 0.0625f, 1.0e6f + 0.125f, 0.0625f}, {x, 1.0e6f, 1}});
    far.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  const Scene distant = Scene::from_mesh(far);
  check_pieces(distant, presplit_references(distant, {.fraction = 2.0f}), 2.0f, true);
}

TEST(Presplit, NonTriangleScenesAreUnchanged) {
  const Scene spheres = bvh_test::random_spheres(200, 3);
  const PresplitResult result = presplit_references(spheres, {.fraction = 1.0f});
  EXPECT_EQ(result.refs.size(), spheres.build_references().size());
  EXPECT_EQ(result.split_triangles, 0u);
  UserPrimitives user;
  user.count = 3;
  user.bounds = [](std::uint32_t id) { return AABB({float(id), 0, 0}, {float(id) + 4, 1, 1}); };
  user.intersect = [](std::uint32_t, const PreparedRay&, Hit&) { return false; };
  const Scene users = Scene::from_user(user);
  EXPECT_EQ(presplit_references(users, {.fraction = 4.0f}).refs.size(), 3u);
}

/// The scene with every vertex multiplied by `factor` (a power of two keeps every coordinate exact).
Scene scaled_copy(const Scene& scene, float factor) {
  TriangleMesh mesh;
  for (std::uint32_t id = 0; id < scene.primitive_count(); ++id) {
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    for (const Vec3& v : scene.triangle(id)) mesh.vertices.push_back(v * factor);
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return Scene::from_mesh(std::move(mesh), scene.name() + " scaled");
}

TEST(PresplitPotential, SeparatesSmallTrianglesFromLargeOnes) {
  // Small triangles on a fine grid waste little box area at coarse planes; long slivers across the scene a lot (the
  // value grows with their count, as the scene box stays the same).
  const Scene grid = Scene::from_mesh(bvh_test::grid_mesh(64), "grid");
  const Scene slivers = make_builtin_scene("slivers", {{"count", "2000"}});
  const double small = presplit_potential(grid, 0);
  const double large = presplit_potential(slivers, 0);
  EXPECT_GE(small, 0.0);
  EXPECT_LT(small, 0.1);
  EXPECT_GT(large, 10.0);
  EXPECT_GE(presplit_potential(diagonal_scene(400, 23), 0), wide::WideBvhOptions{}.presplit_threshold);
}

TEST(PresplitPotential, SampledEstimateIsCloseAndExactWhenAllAreSampled) {
  const Scene slivers = make_builtin_scene("slivers", {{"count", "20000"}});
  const double exact = presplit_potential(slivers, 0);
  EXPECT_EQ(presplit_potential(slivers, 20000), exact);  // n <= max_samples: every triangle, the same sum
  const double sampled = presplit_potential(slivers, 1000);  // every 20th triangle
  EXPECT_NE(sampled, exact);
  EXPECT_NEAR(sampled, exact, 0.2 * exact);
}

TEST(PresplitPotential, IsDimensionless) {
  // Box areas and the scene area scale alike, and the grid planes move with the scene: the same value at any scale.
  const Scene scene = diagonal_scene(300, 5);
  const double unit = presplit_potential(scene, 0);
  for (float factor : {0x1p-20f, 0x1p-3f, 0x1p10f, 0x1p40f}) {
    EXPECT_NEAR(presplit_potential(scaled_copy(scene, factor), 0), unit, 1e-6 * unit) << factor;
  }
}

TEST(PresplitPotential, ZeroWhereNothingCanBeSplit) {
  EXPECT_EQ(presplit_potential(Scene{}), 0.0);
  EXPECT_EQ(presplit_potential(Scene::from_mesh({})), 0.0);
  EXPECT_EQ(presplit_potential(bvh_test::random_spheres(50, 3)), 0.0);
  TriangleMesh point;  // every vertex at one point: a scene box of zero area
  point.vertices = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  point.triangles = {{0, 1, 2}};
  EXPECT_EQ(presplit_potential(Scene::from_mesh(std::move(point))), 0.0);
}

TEST(PresplitWideBvh, DefaultPreSplitsOnlyAboveTheThreshold) {
  const Scene fine = make_builtin_scene("default");  // small triangles: potential far below 4
  const Scene diagonal = diagonal_scene(400, 23);     // far above 4
  const auto references = [](const char* spec, const Scene& scene, double* potential = nullptr) {
    auto accel = make_accelerator(spec);
    accel->build(scene);
    EXPECT_TRUE(accel->validate().empty()) << spec;
    std::map<std::string, double> stats;
    for (const auto& st : accel->build_statistics()) stats[st.name] = st.value;
    if (potential) *potential = stats.at("presplit_potential");
    return stats.at("references");
  };
  double fine_potential = -1.0, diagonal_potential = -1.0;
  EXPECT_EQ(references("bvh_wide", fine, &fine_potential), fine.valid_count());
  EXPECT_GT(references("bvh_wide", diagonal, &diagonal_potential), diagonal.valid_count());
  EXPECT_EQ(fine_potential, presplit_potential(fine));
  EXPECT_EQ(diagonal_potential, presplit_potential(diagonal));
  // threshold 0 always pre-splits; a threshold above the scene's potential turns it off. The potential is reported
  // whatever the options.
  double reported = -1.0;
  EXPECT_GT(references("bvh_wide:presplit_threshold=0", fine, &reported), fine.valid_count());
  EXPECT_EQ(reported, fine_potential);
  EXPECT_EQ(references("bvh_wide:presplit_threshold=1e6", diagonal, &reported), diagonal.valid_count());
  EXPECT_EQ(reported, diagonal_potential);
  EXPECT_EQ(references("bvh_wide:presplit=0", diagonal, &reported), diagonal.valid_count());
  EXPECT_EQ(reported, diagonal_potential);
}

TEST(PresplitWideBvh, ThresholdOptionIsCheckedAndDefaultsToTheConfig) {
  const AcceleratorInfo& info = find_accelerator("bvh_wide");
  const auto option = std::find_if(info.options.begin(), info.options.end(),
                                   [](const OptionSpec& o) { return o.key == "presplit_threshold"; });
  ASSERT_NE(option, info.options.end());
  EXPECT_EQ(std::stof(option->default_value), wide::WideBvhOptions{}.presplit_threshold);
  for (const char* bad : {"bvh_wide:presplit_threshold=-1", "bvh_wide:presplit_threshold=nan",
                          "bvh_wide:presplit_threshold=inf"}) {
    try {
      make_accelerator(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("presplit_threshold"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(make_accelerator("bvh_wide:presplit_threshold=high"), Error);
}

TEST(PresplitWideBvh, ValidatesAndMatchesBruteForce) {
  const Scene scenes[] = {diagonal_scene(800, 11), make_builtin_scene("slivers", {{"count", "1500"}}),
                          bvh_test::random_soup(1500, 13, 0.3f),
                          Scene::from_mesh(bvh_test::grid_mesh(12), "grid")};
  for (const Scene& scene : scenes) {
    const std::vector<Ray> rays = bvh_test::random_rays(scene.bounds(), 3000, 17);
    const bvh_test::OracleAnswers oracle = bvh_test::oracle_answers(scene, rays);
    for (const char* spec : {"bvh_wide", "bvh_wide:presplit=0.3", "bvh_wide:presplit=4,width=4",
                             "bvh_wide:presplit=1,width=8"}) {
      SCOPED_TRACE(scene.name() + " " + spec);
      auto accel = make_accelerator(spec);
      accel->build(scene);
      const std::vector<std::string> problems = accel->validate();
      EXPECT_TRUE(problems.empty()) << problems.front();
      bvh_test::expect_agrees_with_brute_force(*accel, scene, rays, oracle, spec);
    }
  }
}

TEST(PresplitWideBvh, ReportsReferenceCounts) {
  const Scene scene = diagonal_scene(400, 19);
  auto accel = make_accelerator("bvh_wide:presplit=4");
  accel->build(scene);
  std::map<std::string, double> stats;
  for (const auto& s : accel->build_statistics()) stats[s.name] = s.value;
  EXPECT_GT(stats.at("references"), scene.valid_count());
  EXPECT_GT(stats.at("presplit_triangles"), 0.0);
  EXPECT_TRUE(accel->validate().empty());
}

TEST(PresplitWideBvh, RegistryDefaultIsTheConfigDefault) {
  const AcceleratorInfo& info = find_accelerator("bvh_wide");
  const auto option = std::find_if(info.options.begin(), info.options.end(),
                                   [](const OptionSpec& o) { return o.key == "presplit"; });
  ASSERT_NE(option, info.options.end());
  EXPECT_EQ(option->type, OptionType::real);
  EXPECT_EQ(std::stof(option->default_value), wide::WideBvhOptions{}.presplit);
  // The default splits this scene (its potential is above the default threshold); presplit=0 keeps one reference per
  // triangle.
  const Scene scene = diagonal_scene(400, 23);
  for (const auto& [spec, split] : {std::pair{"bvh_wide", true}, std::pair{"bvh_wide:presplit=0", false}}) {
    auto accel = make_accelerator(spec);
    accel->build(scene);
    for (const auto& s : accel->build_statistics()) {
      if (s.name == "references") {
        EXPECT_EQ(s.value > scene.valid_count(), split) << spec;
      }
    }
    EXPECT_TRUE(accel->validate().empty()) << spec;
  }
}

TEST(PresplitWideBvh, RejectsFractionsOutsideRange) {
  for (const char* bad : {"bvh_wide:presplit=-0.1", "bvh_wide:presplit=4.5", "bvh_wide:presplit=1e9"}) {
    try {
      make_accelerator(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      const std::string value = std::string(bad).substr(std::string(bad).find('=') + 1);
      EXPECT_NE(std::string(e.what()).find(value), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("presplit"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(make_accelerator("bvh_wide:presplit=lots"), Error);
  EXPECT_NO_THROW(make_accelerator("bvh_wide:presplit=0"));
  EXPECT_NO_THROW(make_accelerator("bvh_wide:presplit=4"));
}

}  // namespace
}  // namespace rayaccel
