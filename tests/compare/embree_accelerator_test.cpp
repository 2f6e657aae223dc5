// Tests of the Embree comparison wrapper: it agrees with brute force (t within Embree's kernel tolerance), maps
// misses and void rays to this library's miss record, gives the same answers through rtcIntersect8 and rtcOccluded8
// packets as one ray at a time, measures its memory, and refuses non-triangle scenes.
#include "rayaccel/compare/embree_accelerator.h"

#ifdef RAYACCEL_HAVE_EMBREE

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include <embree3/rtcore.h>

#include "rayaccel/accel/brute_force.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/core/query_context.h"
#include "rayaccel/render/camera.h"
#include "rayaccel/render/workloads.h"
#include "rayaccel/scene/builtin_scenes.h"

namespace rayaccel {
namespace {

Scene random_triangles(std::uint32_t count) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  TriangleMesh mesh;
  for (std::uint32_t i = 0; i < count; ++i) {
    const Vec3 c{u(rng), u(rng), u(rng)};
    for (int k = 0; k < 3; ++k) mesh.vertices.push_back(c + Vec3{u(rng), u(rng), u(rng)} * 0.2f);
    mesh.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  return Scene::from_mesh(std::move(mesh), "random");
}

std::vector<Ray> random_rays(std::size_t count) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<Ray> rays(count);
  for (auto& r : rays) {
    r.origin = Vec3{u(rng), u(rng), u(rng)} * 2.0f;
    r.direction = Vec3{u(rng), u(rng), u(rng)} * 0.3f - r.origin;
  }
  return rays;
}

/// One triangle in the plane z = 2 around the z axis, for the hit-interval tests.
Scene triangle_at_z2() {
  TriangleMesh mesh;
  mesh.vertices = {{-1.0f, -1.0f, 2.0f}, {1.0f, -1.0f, 2.0f}, {0.0f, 1.0f, 2.0f}};
  mesh.triangles = {{0, 1, 2}};
  return Scene::from_mesh(mesh);
}

bool agrees(const Hit& a, const Hit& b) {
  if (a.found() != b.found()) return false;
  if (!a.found() || a.prim_id == b.prim_id) return true;
  return std::abs(a.t - b.t) <= 1e-4f * std::abs(b.t);
}

TEST(EmbreeAccelerator, AgreesWithBruteForce) {
  const Scene scene = random_triangles(2000);
  EmbreeAccelerator embree(EmbreeOptions{2, EmbreeBuildQuality::medium});
  embree.build(scene);
  BruteForce oracle;
  oracle.build(scene);
  const auto rays = random_rays(3000);
  std::vector<Hit> got(rays.size()), want(rays.size());
  std::vector<std::uint8_t> got_occ(rays.size()), want_occ(rays.size());
  embree.intersect(rays, got);
  oracle.intersect(rays, want);
  embree.occluded(rays, got_occ);
  oracle.occluded(rays, want_occ);
  std::size_t disagreements = 0, hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    disagreements += agrees(got[i], want[i]) && got_occ[i] == want_occ[i] ? 0 : 1;
    hits += want[i].found() ? 1 : 0;
    if (got[i].found() && got[i].prim_id == want[i].prim_id) {
      EXPECT_NEAR(got[i].u, want[i].u, 1e-3f);
      EXPECT_NEAR(got[i].v, want[i].v, 1e-3f);
    }
  }
  EXPECT_GT(hits, rays.size() / 4);
  EXPECT_EQ(disagreements, 0u);
  EXPECT_TRUE(embree.validate().empty());
  EXPECT_GT(embree.memory_bytes(), 2000u * 8u) << "the memory monitor should see Embree's BVH";
}

TEST(EmbreeAccelerator, MissesAndVoidRaysGiveTheMissRecord) {
  const Scene scene = random_triangles(50);
  EmbreeAccelerator embree;
  embree.build(scene);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<Ray> rays = {
      {{10.0f, 10.0f, 10.0f}, 0.0f, {1.0f, 0.0f, 0.0f}, inf},  // points away
      {{nan, 0.0f, 0.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, inf},
      {{0.0f, 0.0f, -5.0f}, 0.0f, {nan, 0.0f, 1.0f}, inf},
      {{0.0f, 0.0f, -5.0f}, 0.0f, {0.0f, 0.0f, 0.0f}, inf},
      {{0.0f, 0.0f, -5.0f}, nan, {0.0f, 0.0f, 1.0f}, inf},
      {{0.0f, 0.0f, -5.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, 0.0f},  // t_max = 0
      {{0.0f, 0.0f, -5.0f}, 3.0f, {0.0f, 0.0f, 1.0f}, 2.0f},  // t_max < t_min
  };
  for (const Ray& r : rays) {
    const Hit h = embree.intersect(r);
    EXPECT_EQ(h.prim_id, kInvalidPrimId);
    EXPECT_EQ(h.t, inf);
    EXPECT_EQ(h.u, 0.0f);
    EXPECT_EQ(h.v, 0.0f);
    EXPECT_FALSE(embree.occluded(r));
  }
}

TEST(EmbreeAccelerator, HonoursTheHitInterval) {
  const Scene scene = triangle_at_z2();
  EmbreeAccelerator embree;
  embree.build(scene);
  const Ray exact{{0.0f, 0.0f, 0.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, 2.0f};  // t = t_max counts
  EXPECT_EQ(embree.intersect(exact).prim_id, 0u);
  EXPECT_FLOAT_EQ(embree.intersect(exact).t, 2.0f);
  const Ray starts_there{{0.0f, 0.0f, 0.0f}, 2.0f, {0.0f, 0.0f, 1.0f}, 5.0f};  // t = t_min does not
  EXPECT_FALSE(embree.intersect(starts_there).found());
  EXPECT_FALSE(embree.occluded(starts_there));
  const Ray short_ray{{0.0f, 0.0f, 0.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, 1.999f};
  EXPECT_FALSE(embree.occluded(short_ray));
}

/// Rays for the packet tests: camera rays of a 61 x 37 image (2257 rays), with void, empty-interval and t_min-raised
/// rays (`odd`, all but the one at 300 unable to hit) spliced in at positions that fall in different lanes, and a
/// packet of void rays at 400: 2273 rays, so the last packet is partial.
struct PacketRays {
  std::vector<Ray> rays;
  std::vector<std::pair<std::size_t, Ray>> odd;
};

PacketRays packet_rays(const Scene& scene) {
  std::vector<Ray> rays = primary_rays(Camera::framing(scene.bounds()), 61, 37);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<std::pair<std::size_t, Ray>> odd = {
      {0, {{nan, 0.0f, 0.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, inf}},
      {9, {rays[9].origin, 0.0f, {0.0f, 0.0f, 0.0f}, inf}},        // zero direction
      {18, {rays[18].origin, 0.0f, {inf, 0.0f, 1.0f}, inf}},       // infinite direction
      {27, {rays[27].origin, 2.0f, rays[27].direction, 1.0f}},     // t_max < t_min
      {36, {rays[36].origin, 1.0f, rays[36].direction, 1.0f}},     // t_min == t_max: no t fits
      {45, {rays[45].origin, nan, rays[45].direction, inf}},
      {200, {rays[200].origin, 0.0f, rays[200].direction, 0.0f}},  // t_max = 0
      {300, {rays[300].origin, 1e30f, rays[300].direction, inf}},  // starts beyond the scene
  };
  for (const auto& [at, ray] : odd) rays.insert(rays.begin() + static_cast<std::ptrdiff_t>(at), ray);
  // Eight void rays make a whole packet with no active lane (after the odd rays, so their positions hold).
  rays.insert(rays.begin() + 400, 8, Ray{{0.0f, 0.0f, 0.0f}, 0.0f, {0.0f, 0.0f, 0.0f}, inf});
  return {std::move(rays), std::move(odd)};
}

TEST(EmbreeAccelerator, PacketsAgreeWithSingleRays) {
  const Scene scene = make_builtin_scene("default");
  EmbreeAccelerator embree(EmbreeOptions{2, EmbreeBuildQuality::medium});
  embree.build(scene);
  const auto [rays, odd] = packet_rays(scene);
  const float inf = std::numeric_limits<float>::infinity();
  ASSERT_NE(rays.size() % 8, 0u);

  std::vector<Hit> packets(rays.size()), batch(rays.size());
  embree.intersect_packets(rays, packets);
  embree.intersect(rays, batch);
  std::size_t hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hit single = embree.intersect(rays[i]);
    for (const Hit* want : {static_cast<const Hit*>(&batch[i]), &single}) {
      EXPECT_EQ(packets[i].prim_id, want->prim_id) << "ray " << i;
      EXPECT_FLOAT_EQ(packets[i].t, want->t) << "ray " << i;
      EXPECT_FLOAT_EQ(packets[i].u, want->u) << "ray " << i;
      EXPECT_FLOAT_EQ(packets[i].v, want->v) << "ray " << i;
    }
    if (!packets[i].found()) {
      EXPECT_EQ(packets[i].t, inf) << "ray " << i;
      EXPECT_EQ(packets[i].u, 0.0f) << "ray " << i;
      EXPECT_EQ(packets[i].v, 0.0f) << "ray " << i;
    }
    hits += packets[i].found() ? 1 : 0;
  }
  EXPECT_GT(hits, rays.size() / 20) << "the camera should see the scene (about a tenth of its image)";
  for (const auto& [at, ray] : odd) {
    if (at != 300) {
      EXPECT_FALSE(packets[at].found()) << "ray " << at;
    }
  }
  for (std::size_t i = 400; i < 408; ++i) EXPECT_FALSE(packets[i].found()) << "ray " << i;

  // Output slots must match the rays; an empty batch is fine.
  std::vector<Hit> short_output(rays.size() - 1);
  EXPECT_THROW(embree.intersect_packets(rays, short_output), Error);
  embree.intersect_packets({}, {});
}

TEST(EmbreeAccelerator, OccludedPacketsAgreeWithSingleRays) {
  const Scene scene = make_builtin_scene("default");
  EmbreeAccelerator embree(EmbreeOptions{2, EmbreeBuildQuality::medium});
  embree.build(scene);
  auto [rays, odd] = packet_rays(scene);
  // Half the camera rays end halfway to their hit or earlier, so some rays that hit are not occluded.
  std::vector<Hit> hits(rays.size());
  embree.intersect(rays, hits);
  for (std::size_t i = 1; i < rays.size(); i += 2) {
    if (hits[i].found()) rays[i].t_max = 0.5f * hits[i].t;
  }
  std::vector<std::uint8_t> packets(rays.size(), 2), batch(rays.size());  // 2: never written
  embree.occluded_packets(rays, packets);
  embree.occluded(rays, batch);
  std::size_t occluded = 0, shortened = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    EXPECT_EQ(packets[i], batch[i]) << "ray " << i;
    EXPECT_EQ(packets[i], embree.occluded(rays[i]) ? 1 : 0) << "ray " << i;
    occluded += packets[i];
    shortened += i % 2 == 1 && hits[i].found() ? 1 : 0;
  }
  EXPECT_GT(occluded, rays.size() / 40) << "the camera should see the scene";
  EXPECT_GT(shortened, 0u);
  for (const auto& [at, ray] : odd) {
    if (at != 300) {
      EXPECT_EQ(packets[at], 0) << "ray " << at;
    }
  }
  for (std::size_t i = 400; i < 408; ++i) EXPECT_EQ(packets[i], 0) << "ray " << i;
  std::vector<std::uint8_t> short_output(rays.size() - 1);
  EXPECT_THROW(embree.occluded_packets(rays, short_output), Error);
  embree.occluded_packets({}, {});
}

TEST(EmbreeAccelerator, PacketsHonourTheHitInterval) {
  const Scene scene = triangle_at_z2();
  EmbreeAccelerator embree;
  embree.build(scene);
  const std::vector<Ray> rays = {
      {{0.0f, 0.0f, 0.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, 2.0f},    // t = t_max counts
      {{0.0f, 0.0f, 0.0f}, 2.0f, {0.0f, 0.0f, 1.0f}, 5.0f},    // t = t_min does not
      {{0.0f, 0.0f, 0.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, 1.999f},  // ends short
  };
  std::vector<Hit> hits(rays.size());
  embree.intersect_packets(rays, hits);
  EXPECT_EQ(hits[0].prim_id, 0u);
  EXPECT_FLOAT_EQ(hits[0].t, 2.0f);
  EXPECT_FALSE(hits[1].found());
  EXPECT_FALSE(hits[2].found());
  const Scene empty = Scene::from_mesh({});
  EmbreeAccelerator nothing;
  nothing.build(empty);
  nothing.intersect_packets(rays, hits);
  for (const Hit& h : hits) EXPECT_FALSE(h.found());
  // The same interval rules for any hits through rtcOccluded8.
  std::vector<std::uint8_t> occluded(rays.size(), 2);
  embree.occluded_packets(rays, occluded);
  EXPECT_EQ(occluded, (std::vector<std::uint8_t>{1, 0, 0}));
  nothing.occluded_packets(rays, occluded);
  EXPECT_EQ(occluded, (std::vector<std::uint8_t>{0, 0, 0}));
}

TEST(EmbreeAccelerator, InvalidAndZeroAreaTrianglesAreNeverHit) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  TriangleMesh mesh;
  mesh.vertices = {{-1.0f, -1.0f, 1.0f}, {1.0f, -1.0f, 1.0f}, {nan, 1.0f, 1.0f},   // invalid (NaN)
                   {-1.0f, -1.0f, 2.0f}, {1.0f, 1.0f, 2.0f},  {0.0f, 0.0f, 2.0f},   // zero area (collinear)
                   {-1.0f, -1.0f, 3.0f}, {1.0f, -1.0f, 3.0f}, {0.0f, 1.0f, 3.0f}};  // the one a ray can hit
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
  const Scene scene = Scene::from_mesh(mesh);
  EmbreeAccelerator embree;
  embree.build(scene);
  const Hit hit = embree.intersect(Ray{{0.0f, 0.0f, 0.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, 10.0f});
  EXPECT_EQ(hit.prim_id, 2u);
  EXPECT_FLOAT_EQ(hit.t, 3.0f);
}

TEST(EmbreeAccelerator, EmptySceneMissesEverything) {
  const Scene scene = Scene::from_mesh({});
  EmbreeAccelerator embree;
  embree.build(scene);
  EXPECT_FALSE(embree.intersect(Ray{}).found());
  EXPECT_FALSE(embree.occluded(Ray{}));
}

TEST(EmbreeAccelerator, RejectsNonTriangleScenes) {
  const Scene spheres = Scene::from_spheres({{{0.0f, 0.0f, 0.0f}, 1.0f}});
  EmbreeAccelerator embree;
  try {
    embree.build(spheres);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "embree comparison supports triangle scenes only");
  }
}

double statistic(const Accelerator& accel, const std::string& name) {
  for (const auto& s : accel.build_statistics()) {
    if (s.name == name) return s.value;
  }
  ADD_FAILURE() << "no statistic " << name;
  return -1.0;
}

TEST(EmbreeAccelerator, GetsOnlyTheTrianglesOurStructuresBuildOver) {
  // Three zero-area triangles between two valid ones: Embree is handed the two, as brute force and our structures
  // build over them, and reports the scene's id of the second one.
  TriangleMesh mesh;
  mesh.vertices = {{-1.0f, -1.0f, 1.0f}, {1.0f, -1.0f, 1.0f}, {0.0f, 1.0f, 1.0f},  // on the ray's path
                   {5.0f, 5.0f, 1.0f},   {6.0f, 5.0f, 1.0f},  {5.0f, 6.0f, 1.0f}};  // off it
  mesh.triangles = {{3, 4, 5}, {0, 0, 1}, {1, 1, 1}, {2, 2, 0}, {0, 1, 2}};
  const Scene scene = Scene::from_mesh(mesh);
  ASSERT_EQ(scene.valid_count(), 2u);
  EmbreeAccelerator embree;
  embree.build(scene);
  EXPECT_EQ(statistic(embree, "triangles"), 2.0);
  EXPECT_EQ(embree.input_memory_bytes(scene), (6 * 3 + 1) * sizeof(float) + 2 * 3 * sizeof(std::uint32_t));
  const Hit hit = embree.intersect(Ray{{0.0f, 0.0f, 0.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, 10.0f});
  EXPECT_EQ(hit.prim_id, 4u);
}

TEST(EmbreeAccelerator, ContextQueriesGoThroughItsFilterAndAgreeWithBruteForce) {
  // Every control at once on rays whose closest hit brute force knows: each ray skips its own closest primitive (so
  // the skip changes answers), a third of the primitives is switched off, and a filter rejects every fifth.
  const Scene scene = random_triangles(2000);
  BruteForce oracle;
  oracle.build(scene);
  const auto rays = random_rays(3000);
  std::vector<Hit> plain(rays.size());
  oracle.intersect(rays, plain);
  std::vector<std::uint32_t> skip(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) skip[i] = plain[i].prim_id;  // a miss skips nothing
  std::vector<std::uint8_t> enabled(scene.primitive_count());
  for (std::size_t p = 0; p < enabled.size(); ++p) enabled[p] = p % 3 != 1;
  auto reject_every_fifth = [](const HitCandidate& c) { return c.prim_id % 5 != 0; };
  QueryContext context;
  context.skip_primitive = skip;
  context.primitive_enabled = enabled;
  context.set_filter(reject_every_fifth);

  EmbreeAccelerator embree(EmbreeOptions{2, EmbreeBuildQuality::medium, false, true});
  embree.build(scene);
  std::vector<Hit> got(rays.size()), want(rays.size());
  std::vector<std::uint8_t> got_occ(rays.size()), want_occ(rays.size());
  embree.intersect(context, rays, got);
  oracle.intersect(context, rays, want);
  embree.occluded(context, rays, got_occ);
  oracle.occluded(context, rays, want_occ);
  std::size_t disagreements = 0, changed = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    disagreements += agrees(got[i], want[i]) && got_occ[i] == want_occ[i] ? 0 : 1;
    changed += want[i].prim_id != plain[i].prim_id ? 1 : 0;
    if (i % 100 == 0) {
      EXPECT_TRUE(agrees(embree.intersect(context, rays[i], i), want[i])) << "ray " << i;
      EXPECT_EQ(embree.occluded(context, rays[i], i), want_occ[i] != 0) << "ray " << i;
    }
  }
  EXPECT_GT(changed, rays.size() / 4) << "the context should change many answers";
  EXPECT_EQ(disagreements, 0u);

  // Without the scene flag Embree would never call the filter: the context queries refuse instead of ignoring it.
  EmbreeAccelerator unflagged;
  unflagged.build(scene);
  EXPECT_THROW((void)unflagged.intersect(context, rays[0], 0), Error);
  EXPECT_THROW(unflagged.occluded(context, rays, got_occ), Error);
}

TEST(EmbreeAccelerator, RegisteredAsAComparisonEntryWithItsSpecs) {
  const AcceleratorInfo& info = find_accelerator("embree");
  EXPECT_TRUE(info.comparison);
  for (const auto& name : accelerator_variant_names()) EXPECT_NE(parse_accelerator_spec(name).name, "embree") << name;
  const Scene scene = random_triangles(300);
  BruteForce oracle;
  oracle.build(scene);
  const auto rays = random_rays(500);
  struct Case {
    const char* spec;
    RTCBuildQuality quality;
    double robust, threads;
  };
  for (const Case& c : {Case{"embree", RTC_BUILD_QUALITY_MEDIUM, 0, 0}, Case{"embree:quality=high", RTC_BUILD_QUALITY_HIGH, 0, 0},
                        Case{"embree:robust=1", RTC_BUILD_QUALITY_MEDIUM, 1, 0},
                        Case{"embree:quality=low,robust=true,threads=2", RTC_BUILD_QUALITY_LOW, 1, 2}}) {
    auto accel = make_accelerator(c.spec);
    EXPECT_EQ(accel->spec(), c.spec);
    accel->build(scene);
    EXPECT_EQ(statistic(*accel, "build_quality"), static_cast<double>(c.quality)) << c.spec;
    EXPECT_EQ(statistic(*accel, "robust"), c.robust) << c.spec;
    EXPECT_EQ(statistic(*accel, "threads"), c.threads) << c.spec;
    for (const Ray& ray : rays) EXPECT_TRUE(agrees(accel->intersect(ray), oracle.intersect(ray))) << c.spec;
  }
  // The caller's fallback (the CLI's --threads) applies only where the spec leaves threads out.
  EXPECT_EQ(statistic(*make_accelerator("embree", {{"threads", "3"}}), "threads"), 3.0);
  EXPECT_EQ(statistic(*make_accelerator("embree:threads=1", {{"threads", "3"}}), "threads"), 1.0);
  EXPECT_THROW(make_accelerator("embree:quality=best"), Error);
  EXPECT_THROW(make_accelerator("embree:robust=2"), Error);
  EXPECT_THROW(make_accelerator("embree:bins=4"), Error);
}

}  // namespace
}  // namespace rayaccel

#endif  // RAYACCEL_HAVE_EMBREE
