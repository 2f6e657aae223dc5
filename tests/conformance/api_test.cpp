// Conformance: the Accelerator API around the traversal. Batches equal single rays (with and without per-ray
// statistics), statistics do not change answers, a rebuild over another scene forgets the first one.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "oracle.h"
#include "rayaccel/core/error.h"
#include "test_scenes.h"

namespace rayaccel::conformance {
namespace {

class Batch : public ConformanceTest {};
class Statistics : public ConformanceTest {};
class Rebuild : public ConformanceTest {};

/// Batches run the same traversal as single rays, so the answers must be bit-identical.
void expect_identical(const Hit& a, const Hit& b, std::size_t i, const std::string& what) {
  EXPECT_TRUE(a.prim_id == b.prim_id && a.t == b.t && a.u == b.u && a.v == b.v)
      << what << " ray " << i << ": " << describe(a) << " vs single ray " << describe(b);
}

TEST_P(Batch, IntersectAndOccludedEqualSingleRays) {
  const SceneCase& c = small_scene_cases().front();
  auto accel = build_checked(GetParam(), c.scene);
  std::vector<Ray> rays = c.rays;
  const std::vector<Ray> bad = degenerate_rays(c.scene.bounds());
  rays.insert(rays.end(), bad.begin(), bad.end());

  std::vector<Hit> hits(rays.size());
  accel->intersect(rays, hits);
  std::vector<std::uint8_t> occluded(rays.size(), 7);
  accel->occluded(rays, occluded);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    expect_identical(hits[i], accel->intersect(rays[i]), i, "intersect batch");
    EXPECT_EQ(occluded[i], accel->occluded(rays[i]) ? 1 : 0) << "occluded batch ray " << i;
  }
  expect_matches_brute_force(*accel, c.scene, rays, c.name + " (batch rays, single-ray check)");
}

TEST_P(Batch, PerRayStatisticsEqualSingleRayStatistics) {
  const SceneCase& c = small_scene_cases().front();
  auto accel = build_checked(GetParam(), c.scene);
  const std::vector<Ray>& rays = c.rays;
  std::vector<Hit> hits(rays.size());
  std::vector<TraversalStats> stats(rays.size());
  accel->intersect(rays, hits, stats);
  std::vector<std::uint8_t> occluded(rays.size());
  std::vector<TraversalStats> occluded_stats(rays.size());
  accel->occluded(rays, occluded, occluded_stats);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    TraversalStats single;
    expect_identical(hits[i], accel->intersect(rays[i], single), i, "intersect batch with stats");
    EXPECT_EQ(stats[i].nodes_visited, single.nodes_visited) << "ray " << i;
    EXPECT_EQ(stats[i].primitives_tested, single.primitives_tested) << "ray " << i;
    TraversalStats single_occluded;
    EXPECT_EQ(occluded[i], accel->occluded(rays[i], single_occluded) ? 1 : 0) << "ray " << i;
    EXPECT_EQ(occluded_stats[i].nodes_visited, single_occluded.nodes_visited) << "ray " << i;
    EXPECT_EQ(occluded_stats[i].primitives_tested, single_occluded.primitives_tested) << "ray " << i;
  }
}

TEST_P(Batch, EmptyBatchesAndSizeMismatches) {
  const SceneCase& c = small_scene_cases().front();
  auto accel = build_checked(GetParam(), c.scene);
  accel->intersect(std::span<const Ray>{}, std::span<Hit>{});
  accel->occluded(std::span<const Ray>{}, std::span<std::uint8_t>{});
  std::vector<Ray> rays(c.rays.begin(), c.rays.begin() + 4);
  std::vector<Hit> too_few(3);
  std::vector<std::uint8_t> too_many(5);
  std::vector<TraversalStats> wrong_stats(2);
  std::vector<Hit> hits(4);
  EXPECT_THROW(accel->intersect(rays, too_few), Error);
  EXPECT_THROW(accel->occluded(rays, too_many), Error);
  EXPECT_THROW(accel->intersect(rays, hits, wrong_stats), Error);
}

TEST_P(Statistics, CountingDoesNotChangeAnswers) {
  for (const SceneCase& c : small_scene_cases()) {
    auto accel = build_checked(GetParam(), c.scene);
    for (std::size_t i = 0; i < c.rays.size(); ++i) {
      const Ray& ray = c.rays[i];
      TraversalStats stats;
      const Hit counted = accel->intersect(ray, stats);
      expect_identical(counted, accel->intersect(ray), i, c.name + " intersect with stats");
      if (counted.found()) {
        // Reaching a hit means entering at least one node or cell and testing at least one primitive.
        EXPECT_GE(stats.nodes_visited, 1u) << c.name << " ray " << i;
        EXPECT_GE(stats.primitives_tested, 1u) << c.name << " ray " << i;
      }
      TraversalStats occluded_stats;
      EXPECT_EQ(accel->occluded(ray, occluded_stats), accel->occluded(ray)) << c.name << " ray " << i;
    }
  }
}

TEST_P(Rebuild, SecondBuildReplacesTheFirst) {
  const auto& cases = small_scene_cases();
  auto accel = build_checked(GetParam(), cases[0].scene);
  for (std::size_t k = 1; k < cases.size(); ++k) {
    accel->build(cases[k].scene);
    for (const auto& problem : accel->validate()) ADD_FAILURE() << "after rebuild on " << cases[k].name << ": " << problem;
    expect_matches_brute_force(*accel, cases[k].scene, cases[k].rays, "rebuilt on " + cases[k].name);
  }
  const Scene empty = Scene::from_mesh({}, "empty");
  accel->build(empty);
  EXPECT_TRUE(accel->validate().empty());
  for (const Ray& ray : cases[0].rays) ASSERT_FALSE(accel->intersect(ray).found()) << "rebuilt empty: " << describe(ray);
}

INSTANTIATE_TEST_SUITE_P(Conformance, Batch, ::testing::ValuesIn(variant_specs()), spec_test_name);
INSTANTIATE_TEST_SUITE_P(Conformance, Statistics, ::testing::ValuesIn(variant_specs()), spec_test_name);
INSTANTIATE_TEST_SUITE_P(Conformance, Rebuild, ::testing::ValuesIn(variant_specs()), spec_test_name);

}  // namespace
}  // namespace rayaccel::conformance
