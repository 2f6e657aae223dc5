// Uniform grid against brute force: soups, a closed sphere, quad lattices with rays along cell planes, +-0
// directions, spheres; resolution formula, options and validate() (empty and one-triangle scenes: the conformance
// suite, for every structure).
#include "rayaccel/accel/uniform_grid.h"

#include <gtest/gtest.h>

#include "rayaccel/core/error.h"
#include "spatial_oracle.h"

namespace rayaccel {
namespace {

using testing::expect_matches_brute_force;
using testing::expect_valid;

TEST(UniformGrid, ResolutionFollowsExtentAndDensity) {
  const auto cube = grid_resolution({1, 1, 1}, 1000, 3.0, 1024, 1u << 24);
  EXPECT_EQ(cube[0], 30);
  EXPECT_EQ(cube[1], 30);
  EXPECT_EQ(cube[2], 30);
  const auto slab = grid_resolution({4, 1, 1}, 1000, 3.0, 1024, 1u << 24);
  EXPECT_GT(slab[0], 3 * slab[1]);
  const auto flat = grid_resolution({1, 1, 0}, 100, 2.0, 1024, 1u << 24);
  EXPECT_EQ(flat[2], 1);
  EXPECT_NEAR(double(flat[0]) * flat[1], 800.0, 60.0);
  const auto capped = grid_resolution({1, 1, 1}, 1000000, 3.0, 1024, 1000);
  EXPECT_LE(std::uint64_t(capped[0]) * capped[1] * capped[2], 1000u);
  const auto clamped = grid_resolution({100, 1e-3f, 1e-3f}, 1000, 3.0, 64, 1u << 24);
  EXPECT_EQ(clamped[0], 64);
}

TEST(UniformGrid, MatchesBruteForceOnSoupForEveryVariant) {
  const Scene scene = Scene::from_mesh(testing::random_soup(3000, 7));
  const auto rays = testing::random_rays(3000, 11, scene.bounds());
  for (const char* spec : {"grid", "grid:exact=false", "grid:mailbox=false", "grid:blocks=true",
                           "grid:density=1,blocks=true", "grid:density=1,blocks=true,mailbox=true",
                           "grid:density=0.5", "grid:density=1"}) {
    auto grid = make_accelerator(spec);
    grid->build(scene);
    expect_valid(*grid);
    expect_matches_brute_force(*grid, scene, rays, spec);
  }
}

TEST(UniformGrid, MatchesBruteForceOnClosedSphereFromInside) {
  const Scene scene = Scene::from_mesh(testing::closed_sphere(40, 80));
  UniformGrid grid;
  grid.build(scene);
  expect_valid(grid);
  // Rays from inside must always hit the closed surface (watertightness survives the cell walk).
  auto rays = testing::random_rays(2000, 3, AABB({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}), 1.0f);
  for (auto& r : rays) r.t_max = std::numeric_limits<float>::infinity();
  for (const auto& r : rays) EXPECT_TRUE(grid.occluded(r));
  expect_matches_brute_force(grid, scene, rays, "sphere inside");
  expect_matches_brute_force(grid, scene, testing::random_rays(2000, 4, scene.bounds(), 3.0f), "sphere outside");
}

TEST(UniformGrid, RaysAlongCellPlanesOfAQuadLattice) {
  const Scene scene = Scene::from_mesh(testing::quad_lattice(4));
  for (const char* spec : {"grid:density=1", "grid:density=1,blocks=true", "grid:density=2", "grid:exact=false"}) {
    auto accel = make_accelerator(spec);
    accel->build(scene);
    expect_valid(*accel);
    const auto& grid = dynamic_cast<const UniformGrid&>(*accel);
    std::vector<Ray> rays;
    for (int axis = 0; axis < 3; ++axis) {
      for (int along = 0; along < 3; ++along) {
        if (along == axis) continue;
        // Along the grid's own cell planes and along the lattice planes (where the quads lie).
        for (int k = 0; k <= grid.frame().res[axis]; ++k) {
          const auto more = testing::rays_in_plane(axis, grid.frame().plane(axis, k), along, scene.bounds(), 8);
          rays.insert(rays.end(), more.begin(), more.end());
        }
        for (int k = 0; k <= 4; ++k) {
          const auto more = testing::rays_in_plane(axis, float(k), along, scene.bounds(), 8);
          rays.insert(rays.end(), more.begin(), more.end());
        }
      }
    }
    expect_matches_brute_force(*accel, scene, rays, spec);
    expect_matches_brute_force(*accel, scene, testing::random_rays(2000, 5, scene.bounds()), spec);
  }
}

TEST(UniformGrid, RaysAlongCellPlanesThroughFreeQuadEdges) {
  // Density is high and the resolution clamped to 4, so both scenes get the same 4x4x4 frame; the second has
  // quads exactly on that frame's cell planes.
  UniformGridOptions options{.density = 50.0, .max_resolution = 4};
  const Scene pin = Scene::from_mesh(testing::checkerboard_faces(4, [](int, int k) { return float(k); }));
  UniformGrid probe(options);
  probe.build(pin);
  const GridFrame frame = probe.frame();
  // Outer planes stay at the pin scene's bounds (0 and 4) so both scenes share bounds and frame.
  const auto plane = [&](int axis, int k) { return k == 0 || k == 4 ? float(k) : frame.plane(axis, k); };
  const Scene scene = Scene::from_mesh(testing::checkerboard_faces(4, plane));
  for (bool exact : {true, false}) {
    options.exact = exact;
    UniformGrid grid(options);
    grid.build(scene);
    expect_valid(grid);
    ASSERT_EQ(grid.frame().box, frame.box);
    ASSERT_EQ(grid.frame().res, frame.res);
    expect_matches_brute_force(grid, scene, testing::rays_along_planes(4, plane), exact ? "exact" : "boxes");
  }
}

TEST(UniformGrid, RaysStartingOnCellBoundariesAndSurfaces) {
  const Scene scene = Scene::from_mesh(testing::quad_lattice(3));
  UniformGrid grid(UniformGridOptions{.density = 1.0});
  grid.build(scene);
  std::vector<Ray> rays;
  for (int i = 0; i < 64; ++i) {
    Ray r;
    r.origin = {grid.frame().plane(0, i % 4), float(i % 3), grid.frame().plane(2, (i / 4) % 4)};
    r.direction = {float((i % 5) - 2), (i & 1) ? -0.0f : 0.0f, float((i % 7) - 3) + 0.5f};
    rays.push_back(r);
  }
  expect_matches_brute_force(grid, scene, rays, "boundary starts");
}

TEST(UniformGrid, SpheresAndStatistics) {
  std::vector<Sphere> spheres;
  for (int i = 0; i < 200; ++i) spheres.push_back({{float(i % 7), float(i % 11) * 0.5f, float(i % 13) * 0.3f}, 0.2f});
  const Scene scene = Scene::from_spheres(spheres);
  UniformGrid grid;
  grid.build(scene);
  expect_valid(grid);
  expect_matches_brute_force(grid, scene, testing::random_rays(2000, 13, scene.bounds()), "spheres");
  bool has_refs = false;
  for (const auto& s : grid.build_statistics()) {
    if (s.name == "references_per_primitive") has_refs = s.value >= 1.0;
  }
  EXPECT_TRUE(has_refs);
}

TEST(UniformGrid, ExactTestDropsReferences) {
  // A long diagonal sliver: its box spans many cells its triangle never touches.
  TriangleMesh m = testing::random_soup(500, 21, 0.05f);
  const auto base = std::uint32_t(m.vertices.size());
  m.vertices.push_back({-1, -1, -1});
  m.vertices.push_back({1, 1, 1});
  m.vertices.push_back({1, 1, 0.98f});
  m.triangles.push_back({base, base + 1, base + 2});
  const Scene scene = Scene::from_mesh(m);
  const auto refs = [&](const char* spec) {
    auto g = make_accelerator(spec);
    g->build(scene);
    for (const auto& s : g->build_statistics()) {
      if (s.name == "references") return s.value;
    }
    return 0.0;
  };
  EXPECT_LT(refs("grid"), refs("grid:exact=false"));
}

TEST(UniformGrid, BadOptionsAreErrors) {
  EXPECT_THROW(make_accelerator("grid:density=0"), Error);
  EXPECT_THROW(make_accelerator("grid:max_resolution=0"), Error);
  EXPECT_THROW(make_accelerator("grid:max_cells=-5"), Error);
  EXPECT_THROW(make_accelerator("grid:cells=5"), Error);
}

}  // namespace
}  // namespace rayaccel
