// The collapse of bvh_wide (WideBvh::build_from, whose leaf blocks are filled in parallel): the tree, its statistics
// and every answer are the same whatever the number of threads, and malformed binary trees are refused with an error
// instead of being followed out of bounds.
#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <map>
#include <string>

#include "rayaccel/bvh/binned_sah_builder.h"
#include "rayaccel/core/error.h"
#include "rayaccel/scene/builtin_scenes.h"
#include "rayaccel/wide/wide_bvh.h"
#include "wide_test_helpers.h"

namespace rayaccel::wide {
namespace {

class CollapseThreads : public ::testing::TestWithParam<int> {};

TEST_P(CollapseThreads, OneThreadAndSeveralBuildTheSameTree) {
  // The default scene (13,568 triangles) has a few thousand leaves, several ranges of 512 for the parallel block
  // filling; four threads oversubscribe a two-core machine on purpose.
  const Scene scene = make_builtin_scene("default");
  WideBvhOptions config;
  config.width = GetParam();
  WideBvh serial(config), parallel(config);
  tbb::task_arena(1).execute([&] { serial.build(scene); });
  tbb::task_arena(4).execute([&] { parallel.build(scene); });
  EXPECT_TRUE(serial.validate().empty());
  EXPECT_TRUE(parallel.validate().empty());
  EXPECT_GT(statistics(parallel)["triangle4_blocks"], 2048.0) << "too few leaves to be filled in parallel";
  EXPECT_EQ(statistics(serial), statistics(parallel));
  EXPECT_EQ(serial.memory_bytes(), parallel.memory_bytes());
  EXPECT_GT(expect_same_answers(scene, serial, parallel, 3000, 5), 500);
}

INSTANTIATE_TEST_SUITE_P(Widths, CollapseThreads, ::testing::Values(4, 8));

class CollapseSah : public ::testing::TestWithParam<int> {};

TEST_P(CollapseSah, CostsNoMoreThanTheAreaCollapseAndAnswersTheSame) {
  // Without pre-splitting every leaf's blocks are those the plan counts, so the plan's optimum is the tree's cost.
  for (const char* name : {"default", "soup"}) {
    const Scene scene = make_builtin_scene(name);
    WideBvhOptions config;
    config.width = GetParam();
    config.presplit = 0.0f;
    config.collapse = WideCollapse::area;
    WideBvh area(config);
    config.collapse = WideCollapse::sah;
    WideBvh sah(config);
    area.build(scene);
    sah.build(scene);
    EXPECT_TRUE(sah.validate().empty());
    const double area_cost = statistics(area)["sah_cost"], sah_cost = statistics(sah)["sah_cost"];
    EXPECT_GT(sah_cost, 1.0) << name;
    EXPECT_LE(sah_cost, area_cost * (1.0 + 1e-5)) << name;
    EXPECT_EQ(statistics(sah)["references"], statistics(area)["references"]) << name;
    EXPECT_GT(expect_same_answers(scene, area, sah, 3000, 7), 300) << name;
  }
}

INSTANTIATE_TEST_SUITE_P(Widths, CollapseSah, ::testing::Values(4, 8));

/// A two-leaf tree over the default scene's first two triangles, to be broken by the tests below.
BuildTree two_leaf_tree(const Scene& scene) {
  BuildTree tree;
  PrimRefs refs = scene.build_references();
  refs.resize(2);
  tree.refs = std::move(refs);
  tree.nodes = {{1, 0}, {0, 1}, {1, 1}};
  return tree;
}

void expect_refused(const Scene& scene, const BuildTree& tree, const std::string& words) {
  WideBvh bvh;
  try {
    bvh.build_from(scene, tree);
    FAIL() << "expected an error mentioning: " << words;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(CollapseInput, AWellFormedSmallTreeIsAccepted) {
  const Scene scene = make_builtin_scene("default");
  WideBvh bvh;
  bvh.build_from(scene, two_leaf_tree(scene));
  EXPECT_EQ(statistics(bvh)["references"], 2.0);
}

TEST(CollapseInput, ChildrenBeforeTheirParentAreRefused) {
  const Scene scene = make_builtin_scene("default");
  BuildTree tree = two_leaf_tree(scene);
  tree.nodes = {{1, 0}, {0, 0}, {1, 1}};  // node 1 names node 0 (the root) as its child: a cycle
  expect_refused(scene, tree, "not after it");
}

TEST(CollapseInput, ChildrenPastTheLastNodeAreRefused) {
  const Scene scene = make_builtin_scene("default");
  BuildTree tree = two_leaf_tree(scene);
  tree.nodes[0].first = 2;  // children 2 and 3, but there are only three nodes
  expect_refused(scene, tree, "not after it");
}

TEST(CollapseInput, LeavesPastTheLastReferenceAreRefused) {
  const Scene scene = make_builtin_scene("default");
  BuildTree tree = two_leaf_tree(scene);
  tree.nodes[2] = {1, 2};  // references 1 and 2 of two
  expect_refused(scene, tree, "past the end");
}

}  // namespace
}  // namespace rayaccel::wide
