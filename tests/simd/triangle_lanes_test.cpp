// The SIMD triangle tests (four SSE lanes, eight AVX2 lanes, and the eight lanes compiled for AVX-512)
// against the scalar watertight kernel:
// every lane must give the scalar kernel's answer bit for bit (t, u, v and the primitive), including lanes that
// fall back to the scalar kernel (rays through edges and vertices, coordinates outside the safe range) and padding
// lanes, which must never hit.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <random>
#include <vector>

#include "rayaccel/geometry/ray_triangle.h"
#include "rayaccel/simd/isa.h"
#if RAYACCEL_AVX_KERNELS
#include "rayaccel/simd/lanes_avx2.h"
#endif
#include "rayaccel/simd/watertight_lanes.h"

namespace rayaccel::simd {
namespace {

using Triangle = std::array<Vec3, 3>;

void put(Triangle4& block, int lane, const Triangle& t, std::uint32_t id) {
  for (int v = 0; v < 3; ++v) {
    for (int a = 0; a < 3; ++a) block.vertex[v][a][lane] = t[v][a];
  }
  block.prim_id[lane] = id;
}

Triangle4 empty_block() {
  Triangle4 block{};
  for (auto& id : block.prim_id) id = kInvalidPrimId;
  return block;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_same_hit(const Hit& simd, const Hit& scalar, const char* what) {
  EXPECT_TRUE(same_bits(simd.t, scalar.t)) << what << ": t " << simd.t << " vs " << scalar.t;
  EXPECT_EQ(simd.prim_id, scalar.prim_id) << what;
  if (scalar.prim_id != kInvalidPrimId) {
    EXPECT_TRUE(same_bits(simd.u, scalar.u)) << what << ": u";
    EXPECT_TRUE(same_bits(simd.v, scalar.v)) << what << ": v";
  }
}

Hit scalar_hit(const PreparedRay& ray, const Triangle& t, std::uint32_t id) {
  Hit hit = Hit::begin(ray);
  intersect_triangle(ray, t[0], t[1], t[2], id, hit);
  return hit;
}

Hit sse_hit(const PreparedRay& ray, const Triangle4& block) {
  Hit hit = Hit::begin(ray);
  const TrianglePacket<Sse4> packet(ray);
  intersect_triangles4(packet, ray, block, hit);
  return hit;
}

#if RAYACCEL_AVX_KERNELS  // (simd/isa.h: a Clang build has only the SSE kernels)
RAYACCEL_TARGET_AVX2 __attribute__((flatten)) Hit avx_hit(const PreparedRay& ray, const Triangle4& first,
                                                       const Triangle4& second) {
  Hit hit = Hit::begin(ray);
  const TrianglePacket<Avx8> packet(ray);
  const Triangle4* blocks[2] = {&first, &second};
  intersect_triangle_lanes<Avx8>(packet, ray, blocks, hit);
  return hit;
}

/// The same eight-lane test in the AVX-512 build the wide BVH uses where the CPU has it (WideIsa::best).
RAYACCEL_TARGET_AVX512 __attribute__((flatten)) Hit avx512_hit(
    const PreparedRay& ray, const Triangle4& first, const Triangle4& second) {
  Hit hit = Hit::begin(ray);
  const TrianglePacket<Avx8> packet(ray);
  const Triangle4* blocks[2] = {&first, &second};
  intersect_triangle_lanes<Avx8>(packet, ray, blocks, hit);
  return hit;
}
#endif

/// Triangles and rays that exercise every path: random ones, rays aimed exactly at vertices and edge midpoints of
/// axis-aligned triangles (edge functions of exactly zero), and huge and tiny scales (outside the safe range).
struct Case {
  Triangle triangle;
  Ray ray;
};

std::vector<Case> make_cases() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  auto point = [&] { return Vec3{u(rng), u(rng), u(rng)}; };
  std::vector<Case> cases;
  for (int i = 0; i < 3000; ++i) {
    const Triangle t{point(), point(), point()};
    const Vec3 origin = point() * 4.0f;
    const Vec3 target = (t[0] + t[1] + t[2]) * (1.0f / 3.0f) + point() * 0.4f;
    cases.push_back({t, Ray{origin, 0.0f, target - origin, 100.0f}});
  }
  for (int i = 0; i < 600; ++i) {
    const float z = std::round(u(rng) * 4.0f);
    const Triangle t{Vec3{0, 0, z}, Vec3{1, 0, z}, Vec3{0, 1, z}};
    const Vec3 aims[] = {t[0], t[1], t[2], Vec3{0.5f, 0, z}, Vec3{0, 0.5f, z}, Vec3{0.5f, 0.5f, z}};
    const Vec3 target = aims[i % 6];
    const Vec3 origin{std::round(u(rng) * 3.0f), std::round(u(rng) * 3.0f), z + 2.0f + (i % 3)};
    cases.push_back({t, Ray{origin, 0.0f, target - origin, 100.0f}});
  }
  for (int i = 0; i < 6000; ++i) {
    // Aimed at a vertex or an edge's midpoint of a random triangle: float edge functions of exactly zero occur.
    const Triangle t{point(), point(), point()};
    const Vec3 aims[] = {t[0], t[1], t[2], (t[0] + t[1]) * 0.5f, (t[1] + t[2]) * 0.5f, (t[2] + t[0]) * 0.5f};
    const Vec3 target = aims[i % 6];
    const Vec3 origin = i % 2 == 0 ? Vec3{target.x, target.y, target.z + 3.0f} : point() * 4.0f;
    cases.push_back({t, Ray{origin, 0.0f, target - origin, 100.0f}});
  }
  for (float scale : {1e15f, 1e-18f, 0x1p50f, 0x1p-60f}) {
    for (int i = 0; i < 200; ++i) {
      const Triangle t{point() * scale, point() * scale, point() * scale};
      const Vec3 origin = point() * (4.0f * scale);
      const Vec3 target = (t[0] + t[1] + t[2]) * (1.0f / 3.0f);
      cases.push_back({t, Ray{origin, 0.0f, target - origin, 1e30f}});
    }
  }
  return cases;
}

TEST(TriangleLanes, EveryLaneMatchesTheScalarKernelBitForBit) {
  const std::vector<Case> cases = make_cases();
  int hits = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const PreparedRay ray(cases[i].ray);
    const auto id = static_cast<std::uint32_t>(i);
    const Hit expected = scalar_hit(ray, cases[i].triangle, id);
    hits += expected.prim_id != kInvalidPrimId ? 1 : 0;
    for (int lane = 0; lane < 8; ++lane) {
      Triangle4 blocks[2] = {empty_block(), empty_block()};
      put(blocks[lane / 4], lane % 4, cases[i].triangle, id);
      if (lane < 4) expect_same_hit(sse_hit(ray, blocks[0]), expected, "SSE lane");
#if RAYACCEL_AVX_KERNELS
      if (cpu_has_avx2()) expect_same_hit(avx_hit(ray, blocks[0], blocks[1]), expected, "AVX2 lane");
      if (cpu_has_avx512()) expect_same_hit(avx512_hit(ray, blocks[0], blocks[1]), expected, "AVX-512 lane");
#endif
    }
    if (HasFailure()) {
      ADD_FAILURE() << "first failing case " << i;
      return;
    }
  }
  EXPECT_GT(hits, 1000) << "the cases should hit often enough to test the hit path";
}

TEST(TriangleLanes, FullBlocksReturnTheClosestOfTheirTriangles) {
  const std::vector<Case> cases = make_cases();
  std::mt19937 rng(3);
  for (int round = 0; round < 500; ++round) {
    // One ray against eight of the random triangles (distinct t almost surely: the closest is unique).
    const PreparedRay ray(cases[rng() % 3000].ray);
    Triangle4 blocks[2] = {empty_block(), empty_block()};
    Hit expected = Hit::begin(ray);
    for (int lane = 0; lane < 8; ++lane) {
      const auto id = static_cast<std::uint32_t>(rng() % 3000);
      put(blocks[lane / 4], lane % 4, cases[id].triangle, id);
      Hit single = scalar_hit(ray, cases[id].triangle, id);
      if (single.prim_id != kInvalidPrimId && single.t < expected.t) expected = single;
      if (lane == 3) expect_same_hit(sse_hit(ray, blocks[0]), expected, "SSE block");
    }
#if RAYACCEL_AVX_KERNELS
    if (cpu_has_avx2()) expect_same_hit(avx_hit(ray, blocks[0], blocks[1]), expected, "AVX2 pair");
    if (cpu_has_avx512()) expect_same_hit(avx512_hit(ray, blocks[0], blocks[1]), expected, "AVX-512 pair");
#endif
  }
}

TEST(TriangleLanes, PaddingLanesNeverHit) {
  // A zero triangle at the origin in padding lanes; the ray passes through the origin.
  const PreparedRay ray(Ray{Vec3{0.25f, 0.25f, -1.0f}, 0.0f, Vec3{-0.25f, -0.25f, 1.0f}, 10.0f});
  const Triangle4 block = empty_block();
  EXPECT_EQ(sse_hit(ray, block).prim_id, kInvalidPrimId);
#if RAYACCEL_AVX_KERNELS
  if (cpu_has_avx2()) {
    EXPECT_EQ(avx_hit(ray, block, block).prim_id, kInvalidPrimId);
  }
  if (cpu_has_avx512()) {
    EXPECT_EQ(avx512_hit(ray, block, block).prim_id, kInvalidPrimId);
  }
#endif
}

}  // namespace
}  // namespace rayaccel::simd
