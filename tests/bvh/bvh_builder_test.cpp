// The builders on bare references (boxes and ids, no primitives): depth and leaf-size limits on adversarial inputs,
// every reference kept; SBVH reference growth and its memory bound; triangle clipping; option errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "bvh_test_scenes.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/bvh/binned_sah_builder.h"
#include "rayaccel/bvh/bvh.h"
#include "rayaccel/bvh/lbvh_builder.h"
#include "rayaccel/bvh/morton.h"
#include "rayaccel/bvh/ploc_builder.h"
#include "rayaccel/bvh/sweep_sah_builder.h"

namespace rayaccel {
namespace {

/// Levels of the tree; fails the test when a leaf is empty or too large or a reference is lost or repeated.
int check_tree(const BuildTree& tree, std::uint32_t ref_count, std::uint32_t max_leaf) {
  if (ref_count == 0) {
    EXPECT_TRUE(tree.nodes.empty());
    return 0;
  }
  std::vector<int> seen(ref_count, 0);
  int depth = 0;
  std::vector<std::pair<std::uint32_t, int>> pending{{0, 1}};
  while (!pending.empty()) {
    const auto [i, d] = pending.back();
    pending.pop_back();
    depth = std::max(depth, d);
    const BuildNode& n = tree.nodes.at(i);
    if (n.is_leaf()) {
      EXPECT_LE(n.count, max_leaf);
      for (std::uint32_t k = n.first; k < n.first + n.count; ++k) ++seen.at(tree.refs.at(k).prim_id);
    } else {
      pending.push_back({n.first, d + 1});
      pending.push_back({n.first + 1, d + 1});
    }
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<long>(ref_count));
  return depth;
}

PrimRefs identical_boxes(std::uint32_t n) {
  PrimRefs refs;
  for (std::uint32_t i = 0; i < n; ++i) refs.push_back({AABB({0, 0, 0}, {1, 1, 1}), i});
  return refs;
}

/// Boxes at 2^-i along x: the SAH peels one off per level, so without a limit the tree is as deep as the input.
PrimRefs geometric_boxes(std::uint32_t n) {
  PrimRefs refs;
  float x = 1.0f;
  for (std::uint32_t i = 0; i < n; ++i, x *= 0.5f) refs.push_back({AABB({x, 0, 0}, {x * 1.5f, x, x}), i});
  return refs;
}

TEST(BvhBuilders, IdenticalBoxesRespectLeafSize) {
  for (std::uint32_t leaf : {1u, 4u}) {
    EXPECT_LE(check_tree(build_binned_sah(identical_boxes(1000), {leaf, {}, 16, 64}), 1000, leaf), kBvhMaxDepth);
    EXPECT_LE(check_tree(build_sweep_sah(identical_boxes(1000), {leaf, {}, 64}), 1000, leaf), kBvhMaxDepth);
    EXPECT_LE(check_tree(build_lbvh(identical_boxes(1000), {leaf, 64}), 1000, leaf), kBvhMaxDepth);
    EXPECT_LE(check_tree(build_ploc(identical_boxes(1000), {leaf, {}, 8}), 1000, leaf), kBvhMaxDepth);
  }
}

TEST(BvhBuilders, DeepInputStaysWithinDepthLimit) {
  const std::uint32_t n = 120;  // finite floats allow 2^-126 and below, so 120 halvings stay distinct
  EXPECT_LE(check_tree(build_binned_sah(geometric_boxes(n), {1, {}, 16, 64}), n, 1), kBvhMaxDepth);
  EXPECT_LE(check_tree(build_sweep_sah(geometric_boxes(n), {1, {}, 64}), n, 1), kBvhMaxDepth);
  EXPECT_LE(check_tree(build_lbvh(geometric_boxes(n), {1, 64}), n, 1), kBvhMaxDepth);
  EXPECT_LE(check_tree(build_ploc(geometric_boxes(n), {1, {}, 8}), n, 1), kBvhMaxDepth);
  // The unlimited SAH tree would be a chain of n levels; the limit must have cut it.
  EXPECT_GT(check_tree(build_sweep_sah(geometric_boxes(n), {1, {}, 64}), n, 1), kBvhMedianDepth);
}

TEST(BvhBuilders, EmptyInput) {
  EXPECT_TRUE(build_binned_sah({}, {}).nodes.empty());
  EXPECT_TRUE(build_sweep_sah({}, {}).nodes.empty());
  EXPECT_TRUE(build_lbvh({}, {}).nodes.empty());
  EXPECT_TRUE(build_ploc({}, {}).nodes.empty());
}

/// Boxes out to FLT_MAX, ids in the reverse of their order along x: a float centroid of the last box overflows to
/// infinity, and the Morton quantisation made every code 0 (the cast of a NaN cell, found by the fuzz tier under
/// UBSan), so the sort fell back to the ids.
TEST(BvhBuilders, MortonCodesOrderBoxesOutToFltMax) {
  constexpr float kMax = std::numeric_limits<float>::max();
  const float xs[][2] = {{-kMax, -kMax}, {-3e38f, -1e38f}, {0.0f, 1.0f}, {3e38f, kMax}};
  PrimRefs refs;
  for (std::uint32_t i = 0; i < 4; ++i) refs.push_back({AABB({xs[i][0], 0, 0}, {xs[i][1], 1, 1}), 3 - i});
  sort_by_morton_code(refs);
  for (std::uint32_t i = 0; i < 4; ++i) EXPECT_EQ(refs[i].prim_id, 3 - i) << "position " << i;
  EXPECT_LE(check_tree(build_lbvh(refs, {1, 64}), 4, 1), kBvhMaxDepth);
}

/// Long thin diagonal triangles: object splits overlap badly, spatial splits pay off.
Scene diagonal_slivers(std::uint32_t n) {
  TriangleMesh mesh;
  for (std::uint32_t i = 0; i < n; ++i) {
    const float o = 0.01f * static_cast<float>(i);
    mesh.vertices.push_back({o, 0, 0});
    mesh.vertices.push_back({o + 1, 1, 1});
    mesh.vertices.push_back({o + 1.002f, 1, 1});
    mesh.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  return Scene::from_mesh(std::move(mesh), "slivers");
}

TEST(BvhSbvh, SplitsReferencesWithinTheGrowthBound) {
  const Scene scene = diagonal_slivers(400);
  for (float growth : {1.0f, 1.3f, 2.0f}) {
    BvhOptions config;
    config.builder = BvhBuilder::sbvh;
    config.max_growth = growth;
    Bvh<AabbVolume> bvh(config);
    bvh.build(scene);
    EXPECT_TRUE(bvh.validate().empty()) << bvh.validate().front();
    double refs = 0;
    for (const auto& s : bvh.build_statistics()) refs = s.name == "references_per_primitive" ? s.value : refs;
    EXPECT_LE(refs, growth);
    if (growth > 1.0f) {
      EXPECT_GT(refs, 1.05);  // spatial splits were made
    } else {
      EXPECT_EQ(refs, 1.0);
    }
    bvh_test::expect_agrees_with_brute_force(bvh, scene, bvh_test::random_rays(scene.bounds(), 1500, 41),
                                             "sbvh slivers");
  }
}

TEST(BvhSbvh, SpatialSplitsLowerTheSahCost) {
  const Scene scene = diagonal_slivers(400);
  auto sah = [&](BvhBuilder b) {
    BvhOptions config;
    config.builder = b;
    Bvh<AabbVolume> bvh(config);
    bvh.build(scene);
    for (const auto& s : bvh.build_statistics()) {
      if (s.name == "sah_cost") return s.value;
    }
    return 0.0;
  };
  EXPECT_LT(sah(BvhBuilder::sbvh), 0.9 * sah(BvhBuilder::binned));
}

TEST(BvhClip, SbvhReferencePolygonStaysInsideWidenedBox) {
  ClippedPolygon poly;
  const AABB box({0, 0, -1}, {1, 1, 1});
  const int n = clip_triangle_polygon({Vec3{-1, -1, 0}, Vec3{2, -1, 0}, Vec3{0.5f, 2, 0}}, box, poly);
  EXPECT_GE(n, 4);
  for (int i = 0; i < n; ++i) EXPECT_TRUE(widen_for_clipping(box).contains(poly[i]));
  EXPECT_EQ(clip_triangle_polygon({Vec3{2, 2, 2}, Vec3{3, 2, 2}, Vec3{2, 3, 2}}, box, poly), 0);
}

TEST(BvhOptions, BadValuesAreErrorsNamingThem) {
  auto message = [](const std::string& spec) {
    try {
      make_accelerator(spec);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("bvh:leaf_size=0").find("bvh: leaf_size=0 is outside [1, 255]"), std::string::npos);
  EXPECT_NE(message("bvh:leaf_size=-3").find("-3"), std::string::npos);
  EXPECT_NE(message("bvh:bins=1").find("bvh: bins=1 is outside [2, 64]"), std::string::npos);
  EXPECT_NE(message("bvh:max_growth=0.5").find("max_growth"), std::string::npos);
  EXPECT_NE(message("bvh:builder=octree").find("octree"), std::string::npos);
  EXPECT_NE(message("bvh:bv=cone").find("cone"), std::string::npos);
  EXPECT_NE(message("bvh:intersection_cost=0").find("bvh: intersection_cost=0 is outside (0, inf)"), std::string::npos);
}

}  // namespace
}  // namespace rayaccel
