// Conformance: query contexts (core/query_context.h) on every registered structure, against brute force over a copy
// of the scene with the ruled-out primitives made invalid (or, for per-ray skips, a brute-force loop that leaves the
// skipped primitive or geometry out): a hit filter and per-primitive switches rejecting a fixed pseudo-random half,
// ray masks against geometry masks, and a primitive and a geometry skipped per ray; every query form (single ray,
// batch, packets) answers alike.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "oracle.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/core/query_context.h"
#include "test_scenes.h"
#include "../float_specials.h"

namespace rayaccel::conformance {
namespace {

using test_values::kNaN;
constexpr std::size_t kRays = 400;
constexpr std::uint32_t kGeometrySize = 5;  // primitives per geometry in the mask tests

/// The fixed pseudo-random half of the primitives the filter and the switches reject.
bool in_rejected_half(std::uint32_t prim_id) { return ((prim_id * 2654435761u) >> 15) & 1u; }

/// `scene` with every primitive for which drop(id) holds made invalid (ids kept), so brute force over it answers for
/// the others only. Triangles get their own vertex copies (NaN for the dropped ones), spheres a NaN radius.
Scene without(const Scene& scene, const std::function<bool(std::uint32_t)>& drop) {
  const std::uint32_t n = scene.primitive_count();
  if (scene.kind() == PrimitiveKind::spheres) {
    std::vector<Sphere> spheres = scene.spheres();
    for (std::uint32_t id = 0; id < n; ++id) {
      if (drop(id)) spheres[id].radius = kNaN;
    }
    return Scene::from_spheres(std::move(spheres));
  }
  TriangleMesh mesh;
  for (std::uint32_t id = 0; id < n; ++id) {
    const std::array<Vec3, 3> t = scene.triangle(id);
    const bool keep = scene.is_valid(id) && !drop(id);
    for (const Vec3& v : t) mesh.vertices.push_back(keep ? v : Vec3{kNaN, kNaN, kNaN});
    mesh.triangles.push_back({3 * id, 3 * id + 1, 3 * id + 2});
  }
  return Scene::from_mesh(std::move(mesh));
}

/// The scenes of these tests: the small triangle scenes and a sphere scene, kRays rays each.
struct Case {
  std::string name;
  const Scene* scene;
  std::vector<Ray> rays;
};
const std::vector<Case>& cases() {
  static const Scene spheres = random_sphere_scene(800, 31);
  static const std::vector<Case> all = [] {
    std::vector<Case> out;
    for (const SceneCase& c : small_scene_cases()) {
      out.push_back({c.name, &c.scene, std::vector<Ray>(c.rays.begin(), c.rays.begin() + kRays)});
    }
    out.push_back({"spheres", &spheres, random_rays(spheres.bounds(), kRays, 32)});
    return out;
  }();
  return all;
}

/// Per ray index and primitive: true when the context rules the primitive out for that ray.
using RuledOut = std::function<bool(std::size_t, std::uint32_t)>;

/// Compares every query form under `context` (single ray, batch, packets; closest and any hit) with `expected`,
/// checking ties against `reference_scene`; a hit on a primitive `ruled_out` names is a fault even at a tie.
void expect_context_answers(const Accelerator& accel, const QueryContext& context, const Scene& reference_scene,
                            std::span<const Ray> rays, std::span<const Hit> expected, const std::string& label,
                            const RuledOut& ruled_out = [](std::size_t, std::uint32_t) { return false; }) {
  std::vector<Hit> batch(rays.size());
  accel.intersect(context, rays, batch);
  std::vector<std::uint8_t> occluded(rays.size(), 2);
  accel.occluded(context, rays, occluded);
  std::vector<Hit> packets(rays.size());
  accel.intersect_packets(context, rays, packets);
  std::vector<std::uint8_t> occluded_packets(rays.size(), 2);
  accel.occluded_packets(context, rays, occluded_packets);
  int faults = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hit one = accel.intersect(context, rays[i], i);
    std::string fault = hit_mismatch(reference_scene, rays[i], expected[i], one);
    if (fault.empty()) fault = hit_mismatch(reference_scene, rays[i], expected[i], batch[i]);
    if (fault.empty()) fault = hit_mismatch(reference_scene, rays[i], expected[i], packets[i]);
    const Hit* answers[] = {&one, &batch[i], &packets[i]};
    for (const Hit* h : answers) {
      if (fault.empty() && h->found() && ruled_out(i, h->prim_id)) fault = "hit a primitive the context rules out";
    }
    if (fault.empty() && accel.occluded(context, rays[i], i) != expected[i].found()) fault = "occluded(ray) differs";
    if (fault.empty() && occluded[i] != (expected[i].found() ? 1 : 0)) fault = "occluded(batch) differs";
    if (fault.empty() && occluded_packets[i] != (expected[i].found() ? 1 : 0)) fault = "occluded_packets differs";
    if (fault.empty()) continue;
    if (++faults <= 3) {
      ADD_FAILURE() << accel.spec() << " / " << label << " / ray " << i << ": " << fault << "\n  " << describe(rays[i])
                    << "\n  expected " << describe(expected[i]) << "\n  got      " << describe(one);
    }
  }
  EXPECT_EQ(faults, 0) << accel.spec() << " / " << label << ": " << faults << " of " << rays.size() << " rays differ";
}

/// Brute force over `scene` with, per ray, the primitives for which skip(ray index, id) holds left out.
std::vector<Hit> brute_force_skipping(const Scene& scene, std::span<const Ray> rays, const RuledOut& skip) {
  std::vector<Hit> out;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const PreparedRay ray(rays[i]);
    Hit hit = Hit::begin(ray);
    if (!ray.is_void()) {
      for (std::uint32_t id = 0; id < scene.primitive_count(); ++id) {
        if (scene.is_valid(id) && !skip(i, id)) scene.intersect(id, ray, hit);
      }
    }
    hit.finish();
    out.push_back(hit);
  }
  return out;
}

/// Geometry k of a scene in these tests: primitives [k * kGeometrySize, (k + 1) * kGeometrySize).
std::vector<std::uint32_t> geometry_starts(std::uint32_t primitives) {
  std::vector<std::uint32_t> starts;
  for (std::uint32_t first = 0; first < primitives; first += kGeometrySize) starts.push_back(first);
  starts.push_back(primitives);
  return starts;
}

/// Everything a case's checks compare with, computed once for all the structures.
struct Expected {
  Scene half_scene;                  ///< the case's scene without the rejected half
  std::vector<Hit> half;             ///< brute force over half_scene
  std::vector<std::uint32_t> starts;  ///< geometry_starts() of the scene
  std::vector<std::uint32_t> geometry_mask, ray_mask;
  std::vector<Hit> masked;           ///< per ray: brute force over the geometries its mask sees
  std::vector<std::uint32_t> skip_prim, skip_geom;  ///< per ray: brute force's first hit, and its geometry
  std::vector<Hit> skipped_prim, skipped_geom;      ///< brute force without them
};

Expected expect(const Case& c) {
  Expected e;
  const Scene& scene = *c.scene;
  const std::uint32_t n = scene.primitive_count();
  e.half_scene = without(scene, in_rejected_half);
  e.half = brute_force_hits(e.half_scene, c.rays);
  e.starts = geometry_starts(n);
  for (std::size_t g = 0; g + 1 < e.starts.size(); ++g) e.geometry_mask.push_back((g * 2246822519u >> 13) & 3u);
  for (std::size_t i = 0; i < c.rays.size(); ++i) e.ray_mask.push_back(1u + (i % 3 == 0));  // masks 1 and 2
  e.masked = brute_force_skipping(scene, c.rays, [&](std::size_t i, std::uint32_t id) {
    return (e.ray_mask[i] & e.geometry_mask[id / kGeometrySize]) == 0;
  });
  const std::vector<Hit> first = brute_force_hits(scene, c.rays);
  for (const Hit& h : first) {
    e.skip_prim.push_back(h.prim_id);  // kInvalidPrimId for a miss: nothing skipped
    e.skip_geom.push_back(h.found() ? h.prim_id / kGeometrySize : kInvalidPrimId);
  }
  e.skipped_prim =
      brute_force_skipping(scene, c.rays, [&](std::size_t i, std::uint32_t id) { return id == e.skip_prim[i]; });
  e.skipped_geom = brute_force_skipping(
      scene, c.rays, [&](std::size_t i, std::uint32_t id) { return id / kGeometrySize == e.skip_geom[i]; });
  return e;
}

const std::vector<Expected>& expectations() {
  static const std::vector<Expected> all = [] {
    std::vector<Expected> out;
    for (const Case& c : cases()) out.push_back(expect(c));
    return out;
  }();
  return all;
}

void check_filter(const Accelerator& accel, const Case& c, const Expected& e) {
  std::atomic<int> bad_candidates{0};
  auto filter = [&](const HitCandidate& h) {
    // The candidate is a genuine hit of the ray: t in range, the right ray and geometry.
    if (h.ray_index >= c.rays.size() || h.geom_id != 0 || !(h.t > c.rays[h.ray_index].t_min)) ++bad_candidates;
    return !in_rejected_half(h.prim_id);
  };
  QueryContext context;
  context.set_filter(filter);
  expect_context_answers(accel, context, e.half_scene, c.rays, e.half, c.name + " filter");
  EXPECT_EQ(bad_candidates.load(), 0) << c.name;
}

void check_switches(const Accelerator& accel, const Case& c, const Expected& e) {
  std::vector<std::uint8_t> enabled(c.scene->primitive_count());
  for (std::uint32_t id = 0; id < enabled.size(); ++id) enabled[id] = in_rejected_half(id) ? 0 : 1;
  QueryContext context;
  context.primitive_enabled = enabled;
  expect_context_answers(accel, context, e.half_scene, c.rays, e.half, c.name + " primitive_enabled");
}

void check_masks(const Accelerator& accel, const Case& c, const Expected& e) {
  QueryContext context;
  context.geometry_starts = e.starts;
  context.geometry_mask = e.geometry_mask;
  context.ray_mask = e.ray_mask;
  expect_context_answers(accel, context, *c.scene, c.rays, e.masked, c.name + " masks",
                         [&](std::size_t i, std::uint32_t id) {
                           return (e.ray_mask[i] & e.geometry_mask[id / kGeometrySize]) == 0;
                         });
}

void check_skips(const Accelerator& accel, const Case& c, const Expected& e) {
  QueryContext context;
  context.skip_primitive = e.skip_prim;
  expect_context_answers(accel, context, *c.scene, c.rays, e.skipped_prim, c.name + " skip_primitive",
                         [&](std::size_t i, std::uint32_t id) { return id == e.skip_prim[i]; });
  QueryContext by_geometry;
  by_geometry.geometry_starts = e.starts;
  by_geometry.skip_geometry = e.skip_geom;
  expect_context_answers(accel, by_geometry, *c.scene, c.rays, e.skipped_geom, c.name + " skip_geometry",
                         [&](std::size_t i, std::uint32_t id) { return id / kGeometrySize == e.skip_geom[i]; });
}

class QueryContextTest : public ConformanceTest {};

/// One build per scene serves the four checks (the suite runs over every variant: builds dominate its time).
TEST_P(QueryContextTest, FilterSwitchesMasksAndSkipsMatchBruteForce) {
  for (std::size_t k = 0; k < cases().size(); ++k) {
    const Case& c = cases()[k];
    const Expected& e = expectations()[k];
    auto accel = build_checked(GetParam(), *c.scene);
    check_filter(*accel, c, e);
    check_switches(*accel, c, e);
    check_masks(*accel, c, e);
    check_skips(*accel, c, e);
  }
}

INSTANTIATE_TEST_SUITE_P(Conformance, QueryContextTest, ::testing::ValuesIn(variant_specs()), spec_test_name);

TEST(QueryContext, BadArraySizesAreNamed) {
  const Scene& scene = small_scene_cases()[0].scene;
  auto accel = make_accelerator("brute_force");
  accel->build(scene);
  const std::vector<Ray> rays(4);
  std::vector<Hit> hits(4);
  const std::vector<std::uint32_t> skip(3, 0);
  QueryContext context;
  context.skip_primitive = skip;
  try {
    accel->intersect(context, rays, hits);
    ADD_FAILURE() << "no error for 3 skip entries and 4 rays";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("skip_primitive has 3 entries for 4 rays"), std::string::npos) << e.what();
  }
  EXPECT_THROW(accel->intersect(context, rays[0], 3), Error);
  EXPECT_NO_THROW(accel->intersect(context, rays[0], 2));
}

}  // namespace
}  // namespace rayaccel::conformance
