// Conformance: every registered structure against exact rational arithmetic on rays from 1 to 1e6 scene sizes away
// with direction lengths from 1e-6 to 1e6, over closed meshes (shared edges), a soup of overlapping triangles and
// scaled, offset copies. The exact answers are computed once per scene and shared by every structure.
#include <gtest/gtest.h>

#include "../conformance/oracle.h"
#include "../conformance/test_scenes.h"
#include "exact_reference.h"
#include "far_rays.h"

namespace rayaccel::exact {
namespace {

struct ExactCase {
  std::string name;
  Scene scene;
  std::vector<Ray> rays;
  std::vector<std::vector<ExactHit>> exact;
};

const std::vector<ExactCase>& exact_cases() {
  static const std::vector<ExactCase> cases = [] {
    const std::vector<std::pair<std::string, TriangleMesh>> meshes = {
        {"closed sphere", conformance::closed_sphere_mesh(10, 20)},
        {"soup", conformance::random_soup_mesh(150, 0.3f, 5)},
        {"box x1e3 at 1e4", conformance::transformed(conformance::closed_box_mesh(4), 1e3f, {1e4f, -2e4f, 3e4f})},
        {"sphere x1e-3 at 10", conformance::transformed(conformance::closed_sphere_mesh(8, 12), 1e-3f, {10, 0, 0})},
    };
    std::vector<ExactCase> out;
    std::uint64_t seed = 100;
    for (const auto& [name, mesh] : meshes) {
      ExactCase c{name, Scene::from_mesh(mesh, name), far_rays(mesh, kSceneSizesAway, kDirectionLengths, 6, ++seed),
                  {}};
      c.exact = exact_hits(ExactReference(mesh), c.rays);
      out.push_back(std::move(c));
    }
    return out;
  }();
  return cases;
}

class ExactFarRays : public conformance::ConformanceTest {};

TEST_P(ExactFarRays, AgreeWithExactArithmetic) {
  for (const ExactCase& c : exact_cases()) {
    auto accel = conformance::build_checked(GetParam(), c.scene);
    expect_exact_answers(*accel, c.rays, c.exact, GetParam() + " on " + c.name);
  }
}

INSTANTIATE_TEST_SUITE_P(Conformance, ExactFarRays, ::testing::ValuesIn(conformance::variant_specs()),
                         conformance::spec_test_name);

}  // namespace
}  // namespace rayaccel::exact
