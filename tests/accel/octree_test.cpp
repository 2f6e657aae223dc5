// Octree against brute force: soups, a closed sphere, checkerboard faces on the octree's own cell planes, +-0
// directions, empty and one-triangle scenes; insertion and removal in random order checked against a brute-force
// loop over exactly the active set, with validate() after every batch.
#include "rayaccel/accel/octree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "rayaccel/core/error.h"
#include "spatial_oracle.h"

namespace rayaccel {
namespace {

using testing::expect_matches_brute_force;
using testing::expect_valid;

TEST(Octree, MatchesBruteForceOnSoupForEveryVariant) {
  const Scene scene = Scene::from_mesh(testing::random_soup(2000, 43));
  const auto rays = testing::random_rays(2000, 47, scene.bounds());
  for (const char* spec : {"octree", "octree:exact=false", "octree:mailbox=false", "octree:max_prims=2,max_depth=6",
                           "octree:max_depth=1"}) {
    auto tree = make_accelerator(spec);
    tree->build(scene);
    expect_valid(*tree);
    expect_matches_brute_force(*tree, scene, rays, spec);
  }
}

TEST(Octree, ClosedSphereFromInsideAndOutside) {
  const Scene scene = Scene::from_mesh(testing::closed_sphere(40, 80));
  Octree tree;
  tree.build(scene);
  expect_valid(tree);
  auto rays = testing::random_rays(2000, 53, AABB({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}), 1.0f);
  for (auto& r : rays) r.t_max = std::numeric_limits<float>::infinity();
  for (const auto& r : rays) EXPECT_TRUE(tree.occluded(r));
  expect_matches_brute_force(tree, scene, rays, "sphere inside");
  expect_matches_brute_force(tree, scene, testing::random_rays(2000, 59, scene.bounds(), 3.0f), "sphere outside");
}

TEST(Octree, RaysAlongCellPlanesThroughFreeQuadEdges) {
  // With the root [0, 4]^3 the cell planes of depth 2 are the integers, where the checkerboard quads lie.
  const Scene scene = Scene::from_mesh(testing::checkerboard_faces(4, [](int, int k) { return float(k); }));
  const auto plane = [](int, int k) { return float(k); };
  for (bool exact : {true, false}) {
    OctreeOptions options;
    options.root_bounds = AABB({0, 0, 0}, {4, 4, 4});
    options.max_prims = 2;
    options.max_depth = 4;
    options.exact = exact;
    Octree tree(options);
    tree.build(scene);
    expect_valid(tree);
    expect_matches_brute_force(tree, scene, testing::rays_along_planes(4, plane), exact ? "exact" : "boxes");
    expect_matches_brute_force(tree, scene, testing::random_rays(1500, 61, scene.bounds()), "random");
  }
  const Scene lattice = Scene::from_mesh(testing::quad_lattice(4));
  Octree tree;
  tree.build(lattice);
  expect_valid(tree);
  expect_matches_brute_force(tree, lattice, testing::rays_along_planes(4, plane), "lattice");
}

TEST(Octree, EmptySceneSingleTriangleAndSpheres) {
  Octree tree;
  const Scene empty = Scene::from_mesh({});
  tree.build(empty);
  expect_valid(tree);
  EXPECT_FALSE(tree.intersect(Ray{{0, 0, -1}, 0, {0, 0, 1}}).found());

  TriangleMesh one;
  one.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  one.triangles = {{0, 1, 2}};
  const Scene single = Scene::from_mesh(one);
  tree.build(single);
  expect_valid(tree);
  EXPECT_FLOAT_EQ(tree.intersect(Ray{{0.25f, 0.25f, -1}, 0, {0, 0, 1}}).t, 1.0f);
  EXPECT_FALSE(tree.intersect(Ray{{0.25f, 0.25f, -1}, 0, {0, 0, 1}, 0.0f}).found());
  expect_matches_brute_force(tree, single, testing::random_rays(500, 67, single.bounds()), "single");

  std::vector<Sphere> spheres;
  for (int i = 0; i < 300; ++i) spheres.push_back({{float(i % 7), float(i % 11) * 0.5f, float(i % 13) * 0.3f}, 0.15f});
  const Scene balls = Scene::from_spheres(spheres);
  tree.build(balls);
  expect_valid(tree);
  expect_matches_brute_force(tree, balls, testing::random_rays(1500, 71, balls.bounds()), "spheres");
}

/// Closest hit over exactly the primitives the tree holds.
Hit brute_force_over_active(const Scene& scene, const Octree& tree, const Ray& ray) {
  const PreparedRay pr(ray);
  Hit hit = Hit::begin(pr);
  if (!pr.is_void()) {
    for (std::uint32_t id = 0; id < scene.primitive_count(); ++id) {
      if (tree.is_active(id)) scene.intersect(id, pr, hit);
    }
  }
  hit.finish();
  return hit;
}

void expect_matches_active_set(const Scene& scene, const Octree& tree, const std::vector<Ray>& rays) {
  int failures = 0;
  for (std::size_t i = 0; i < rays.size() && failures < 5; ++i) {
    const Hit want = brute_force_over_active(scene, tree, rays[i]);
    const Hit got = tree.intersect(rays[i]);
    const bool same = want.found() == got.found() && tree.occluded(rays[i]) == want.found() &&
                      (!want.found() || (want.t == got.t && (want.prim_id == got.prim_id || want.t == got.t)));
    if (!same) {
      ++failures;
      ADD_FAILURE() << "ray " << i << ": active-set brute force t=" << want.t << " prim=" << want.prim_id
                    << ", octree t=" << got.t << " prim=" << got.prim_id;
    }
  }
}

TEST(Octree, InsertAndRemoveInRandomOrderMatchTheActiveSet) {
  Scene scene = Scene::from_mesh(testing::random_soup(400, 73, 0.15f));
  OctreeOptions options;
  options.pad = 0.25;
  options.max_prims = 4;
  Octree tree(options);
  tree.build(scene);
  expect_valid(tree);
  // The scene gains 400 more triangles after the build.
  TriangleMesh extra = testing::random_soup(400, 79, 0.15f);
  const auto old_vertices = std::uint32_t(scene.mesh().vertices.size());
  for (auto& t : extra.triangles) t = {t[0] + old_vertices, t[1] + old_vertices, t[2] + old_vertices};
  const auto first_new = scene.append_triangles(extra.vertices, extra.triangles);
  std::vector<std::uint32_t> ops(800);
  std::iota(ops.begin(), ops.end(), 0u);
  std::mt19937 rng(83);
  std::shuffle(ops.begin(), ops.end(), rng);
  const auto rays = testing::random_rays(600, 89, scene.bounds());
  // Each batch toggles 100 primitives: new ones go in, old ones come out (and some come back later).
  for (std::size_t batch = 0; batch < ops.size(); batch += 100) {
    for (std::size_t i = batch; i < batch + 100; ++i) {
      const std::uint32_t id = ops[i] < 400 ? ops[i] : first_new + (ops[i] - 400);
      if (tree.is_active(id)) {
        tree.remove(id);
      } else {
        tree.insert(id);
      }
    }
    if (batch == 400) {
      for (std::uint32_t id = 0; id < 400; id += 3) {
        if (!tree.is_active(id)) tree.insert(id);
      }
    }
    expect_valid(tree);
    expect_matches_active_set(scene, tree, rays);
  }
  // Remove everything: sibling leaves merge back into a single empty root.
  for (std::uint32_t id = 0; id < scene.primitive_count(); ++id) {
    if (tree.is_active(id)) tree.remove(id);
  }
  expect_valid(tree);
  EXPECT_EQ(tree.active_count(), 0u);
  for (const auto& s : tree.build_statistics()) {
    if (s.name == "leaves") {
      EXPECT_EQ(s.value, 1.0);
    }
  }
  expect_matches_active_set(scene, tree, rays);
  // Refilled in id order, the tree answers like a fresh build.
  for (std::uint32_t id = 0; id < scene.primitive_count(); ++id) tree.insert(id);
  expect_valid(tree);
  expect_matches_brute_force(tree, scene, rays, "refilled");
}

TEST(Octree, UpdateErrorsNameTheProblem) {
  Scene scene = Scene::from_mesh(testing::random_soup(50, 97));
  Octree tree;
  EXPECT_THROW(tree.insert(0), Error);
  tree.build(scene);
  EXPECT_THROW(tree.insert(0), Error);       // already present
  EXPECT_THROW(tree.insert(50), Error);      // out of range
  tree.remove(7);
  EXPECT_THROW(tree.remove(7), Error);       // not present
  const TriangleMesh far = testing::random_soup(1, 101);
  TriangleMesh moved = far;
  for (auto& v : moved.vertices) v = v + Vec3{100, 0, 0};
  const auto old_vertices = std::uint32_t(scene.mesh().vertices.size());
  for (auto& t : moved.triangles) t = {t[0] + old_vertices, t[1] + old_vertices, t[2] + old_vertices};
  const auto id = scene.append_triangles(moved.vertices, moved.triangles);
  try {
    tree.insert(id);
    ADD_FAILURE() << "insert outside the root box did not throw";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("root box"), std::string::npos) << e.what();
  }
  expect_valid(tree);
  EXPECT_THROW(make_accelerator("octree:max_depth=0"), Error);
  EXPECT_THROW(make_accelerator("octree:max_depth=40"), Error);
  EXPECT_THROW(make_accelerator("octree:max_prims=0"), Error);
  EXPECT_THROW(make_accelerator("octree:pad=-1"), Error);
  OctreeOptions small;
  small.root_bounds = AABB({0, 0, 0}, {0.1f, 0.1f, 0.1f});
  Octree bounded(small);
  EXPECT_THROW(bounded.build(scene), Error);
}

}  // namespace
}  // namespace rayaccel
