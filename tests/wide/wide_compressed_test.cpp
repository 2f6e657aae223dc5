// bvh_wide's compressed nodes (compress=1): the 8-bit grid holds every child box, rounded outward and decoded
// exactly, at every scale and offset; single rays then get bit for bit the full nodes' answers on both eight-wide
// paths, far origins included; refit and load keep the compressed copy.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <utility>

#include "rayaccel/accel/registry.h"
#include "rayaccel/scene/builtin_scenes.h"
#include "rayaccel/simd/isa.h"
#include "rayaccel/wide/compressed_node.h"
#include "rayaccel/wide/wide_bvh.h"
#include "wide_test_helpers.h"

namespace rayaccel::wide {
namespace {

/// A node of up to eight random children inside [offset, offset + size] on each axis (lanes from `used` on empty).
Node<8> random_node(std::mt19937& rng, double offset, double size, int used) {
  Node<8> node{};
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int lane = 0; lane < 8; ++lane) {
    node.child[lane] = lane < used ? static_cast<std::uint32_t>(lane + 1) : kEmptyChild;
    AABB box = AABB::empty();
    if (lane < used) {
      for (int a = 0; a < 3; ++a) {
        double x = offset + size * u(rng), y = offset + size * u(rng);
        if (lane == 0) y = x;  // a flat child
        box.lo[a] = static_cast<float>(std::min(x, y));
        box.hi[a] = static_cast<float>(std::max(x, y));
      }
    }
    set_child_bounds(node, lane, box);
  }
  set_child_order(node);
  return node;
}

TEST(CompressNode, GridBoxesContainTheChildrenAtEveryScaleAndOffset) {
  std::mt19937 rng(5);
  int checked = 0;
  for (double size : {0.0, 1e-30, 1e-6, 1.0, 1e6, 1e30}) {
    for (double offset : {0.0, 1.0, -1e4, 1e7, -3e20, 1e35}) {
      for (int used : {1, 2, 5, 8}) {
        const Node<8> node = random_node(rng, offset, size, used);
        CompressedNode8 c;
        ASSERT_TRUE(compress_node(node, c)) << "size " << size << " offset " << offset;
        for (int lane = 0; lane < 8; ++lane) {
          ASSERT_EQ(c.child[lane], node.child[lane]);
          if (node.child[lane] == kEmptyChild) continue;
          const AABB box = child_bounds(node, lane), grid = decoded_child_bounds(c, lane);
          EXPECT_TRUE(grid.contains(box)) << "size " << size << " offset " << offset << " lane " << lane;
          for (int a = 0; a < 3; ++a) {
            // The decoding is exact: the float sum equals the real one.
            for (int side = 0; side < 2; ++side) {
              const double exact = double(c.origin[a]) + double(c.q[a][side][lane]) * double(c.scale[a]);
              EXPECT_EQ(exact, double(side ? grid.hi[a] : grid.lo[a]));
            }
            // Loose by less than a grid step on each side, and the step is fine: at most the node's extent / 127,
            // or 2^-22 of its largest coordinate's magnitude where that is coarser (floats run out of bits there).
            EXPECT_LT(double(box.lo[a]) - grid.lo[a], double(c.scale[a]));
            EXPECT_LT(double(grid.hi[a]) - box.hi[a], double(c.scale[a]));
            const double magnitude = std::fabs(offset) + size;
            EXPECT_LE(double(c.scale[a]), std::max({size / 127.0, magnitude * 0x1p-22, 0x1p-100}))
                << "size " << size << " offset " << offset;
          }
          ++checked;
        }
        for (unsigned octant = 0; octant < 8; ++octant) EXPECT_EQ(child_order(c, octant), child_order(node, octant));
      }
    }
  }
  EXPECT_GT(checked, 500);
}

TEST(CompressNode, RefusesBoxesBeyondTheGridsRange) {
  std::mt19937 rng(6);
  CompressedNode8 c;
  EXPECT_FALSE(compress_node(random_node(rng, -3e38, 6e38, 4), c));
  EXPECT_FALSE(compress_node(random_node(rng, 3e38, 1e30, 2), c));
}

/// Rays from `distance` scene sizes away (direction lengths varied) towards random points of the scene's box.
std::vector<Ray> far_rays(const Scene& scene, float distance, int count, unsigned seed) {
  const AABB box = scene.bounds();
  const Vec3 centre = (box.lo + box.hi) * 0.5f;
  const float size = length(box.hi - box.lo);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::normal_distribution<float> n(0.0f, 1.0f);
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    const Vec3 away = normalize(Vec3{n(rng), n(rng), n(rng)});
    const Vec3 origin = centre + away * (distance * size);
    const Vec3 target{box.lo.x + u(rng) * (box.hi.x - box.lo.x), box.lo.y + u(rng) * (box.hi.y - box.lo.y),
                      box.lo.z + u(rng) * (box.hi.z - box.lo.z)};
    const float direction_length = std::pow(10.0f, float(i % 7) - 3.0f);
    rays.push_back({origin, 0.0f, normalize(target - origin) * direction_length,
                    std::numeric_limits<float>::infinity()});
  }
  return rays;
}

void expect_same_far_answers(const Scene& scene, const Accelerator& full, const Accelerator& compressed,
                             const std::string& what) {
  int hits = 0;
  // Fewer rays from farther: there the triangle test settles most edges exactly, which is slow.
  for (const auto& [distance, count] : {std::pair{1.0f, 300}, std::pair{1e3f, 150}, std::pair{1e6f, 30}}) {
    for (const Ray& ray : far_rays(scene, distance, count, 9)) {
      // The same t bit for bit; from far away, float t ties between neighbouring triangles, and a tie may go to
      // either (the conformance oracle's rule), as the two trees may meet the triangles in another order.
      const Hit a = full.intersect(ray), b = compressed.intersect(ray);
      ASSERT_EQ(std::memcmp(&a.t, &b.t, sizeof a.t), 0) << what << " at " << distance;
      ASSERT_EQ(a.prim_id == kInvalidPrimId, b.prim_id == kInvalidPrimId) << what << " at " << distance;
      ASSERT_EQ(full.occluded(ray), compressed.occluded(ray)) << what << " at " << distance;
      hits += a.prim_id != kInvalidPrimId ? 1 : 0;
    }
  }
  EXPECT_GT(hits, 60) << what << ": rays aimed into the box should hit often";
}

TEST(WideCompressed, SingleRaysGetTheFullNodesAnswersOnBothEightWidePaths) {
  if (simd::best_isa() == simd::Isa::sse2) GTEST_SKIP() << "no eight-wide kernels on this CPU";
  for (const char* name : {"default", "soup"}) {
    const Scene scene = make_builtin_scene(name);
    // Also the scene moved far from the origin and shrunk, where the grid's steps meet float's.
    for (const std::string& spec : {std::string("bvh_wide:compress=1"),
                                    std::string("bvh_wide:width=8,isa=avx2,compress=1")}) {
      auto full = make_accelerator("bvh_wide");
      auto compressed = make_accelerator(spec);
      full->build(scene);
      compressed->build(scene);
      const auto stats = statistics(*compressed);
      ASSERT_GT(stats.at("nodes"), 0.0);
      EXPECT_EQ(stats.at("compressed_nodes"), stats.at("nodes")) << spec << ": the compressed copy must be in use";
      EXPECT_TRUE(compressed->validate().empty());
      EXPECT_GT(expect_same_answers(scene, *full, *compressed, 3000, 12), 500) << spec << " on " << name;
      expect_same_far_answers(scene, *full, *compressed, spec + " on " + name);
    }
  }
}

TEST(WideCompressed, RefitAndLoadKeepTheCompressedCopy) {
  if (simd::best_isa() == simd::Isa::sse2) GTEST_SKIP() << "no eight-wide kernels on this CPU";
  Scene scene = make_builtin_scene("default");
  WideBvh compressed(WideBvhOptions{.compress = true});
  compressed.build(scene);
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "wide_compressed_test.rbvh";
  compressed.save(file);
  std::vector<Vec3> moved = scene.mesh().vertices;
  for (Vec3& v : moved) v = v * 1.5f + Vec3{0.25f, 0.0f, -3.0f};
  scene.set_vertices(moved);
  compressed.refit();
  EXPECT_TRUE(compressed.validate().empty());
  EXPECT_EQ(statistics(compressed).at("compressed_nodes"), statistics(compressed).at("nodes"));
  auto full = make_accelerator("bvh_wide");
  full->build(scene);
  EXPECT_GT(expect_same_answers(scene, *full, compressed, 2000, 13), 300);
  // A file holds the full nodes; a compress=1 object compresses them on load.
  Scene original = make_builtin_scene("default");
  WideBvh loaded(WideBvhOptions{.compress = true});
  loaded.load(file, original);
  std::filesystem::remove(file);
  EXPECT_EQ(statistics(loaded).at("compressed_nodes"), statistics(loaded).at("nodes"));
  full->build(original);
  EXPECT_GT(expect_same_answers(original, *full, loaded, 2000, 14), 300);
}

}  // namespace
}  // namespace rayaccel::wide
