// Every bvh variant (volume x builder) against brute force on soups, a closed sphere, flat and coplanar geometry,
// duplicates, spheres, an empty scene and a single triangle; each build must also pass validate().
#include <gtest/gtest.h>

#include <cctype>
#include <map>

#include "bvh_test_scenes.h"
#include "rayaccel/accel/registry.h"

namespace rayaccel {
namespace {

using bvh_test::expect_agrees_with_brute_force;
using bvh_test::random_rays;

std::vector<std::string> bvh_variants() {
  std::vector<std::string> out;
  for (const auto& name : accelerator_variant_names()) {
    if (name.rfind("bvh:", 0) == 0) out.push_back(name);
  }
  return out;
}

class BvhVariant : public ::testing::TestWithParam<std::string> {
 protected:
  /// Scenes are rebuilt per test from fixed seeds; the brute-force answers are computed once per test name.
  void check(const Scene& scene, std::uint32_t ray_count, const std::string& extra = "") {
    static std::map<std::string, bvh_test::OracleAnswers> cache;
    const std::string spec = GetParam() + extra;
    auto accel = make_accelerator(spec);
    accel->build(scene);
    const auto problems = accel->validate();
    EXPECT_TRUE(problems.empty()) << spec << " on " << scene.name() << ": " << problems.front();
    const auto rays = random_rays(scene.bounds(), ray_count, 7);
    const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    const std::string key = test.substr(0, test.find('/'));  // the scene, without the variant
    auto it = cache.find(key);
    if (it == cache.end()) it = cache.emplace(key, bvh_test::oracle_answers(scene, rays)).first;
    expect_agrees_with_brute_force(*accel, scene, rays, it->second, spec + " " + scene.name());
  }
};

TEST_P(BvhVariant, RandomSoup) { check(bvh_test::random_soup(3000, 1), 3000); }
TEST_P(BvhVariant, RandomSoupLeafSizeOne) { check(bvh_test::random_soup(500, 2), 1000, ",leaf_size=1"); }
TEST_P(BvhVariant, LargeTrianglesSoup) { check(bvh_test::random_soup(400, 3, 0.8f), 2000); }
TEST_P(BvhVariant, ClosedSphereMesh) {
  check(Scene::from_mesh(bvh_test::sphere_mesh(24, 48), "sphere_mesh"), 3000);
}
TEST_P(BvhVariant, FlatGrid) { check(Scene::from_mesh(bvh_test::grid_mesh(30), "grid"), 2000); }
TEST_P(BvhVariant, CoplanarAndDuplicates) { check(bvh_test::coplanar_and_duplicates(4), 2000); }
TEST_P(BvhVariant, Spheres) { check(bvh_test::random_spheres(500, 5), 2000); }
TEST_P(BvhVariant, EmptyScene) { check(Scene::from_mesh({}, "empty"), 50); }
TEST_P(BvhVariant, SingleTriangle) {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}};
  check(Scene::from_mesh(std::move(mesh), "single"), 200);
}

INSTANTIATE_TEST_SUITE_P(AllBvhVariants, BvhVariant, ::testing::ValuesIn(bvh_variants()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           std::string name = param.param.substr(4);
                           for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });

}  // namespace
}  // namespace rayaccel
