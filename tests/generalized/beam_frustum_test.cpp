// The float frustum's box culling on every lane set (SSE, AVX2, AVX-512 where the CPU has them): a box that holds a
// point exactly on a ray the frustum holds is never culled, with the slack off so the rounding margin alone must keep
// it, near the origin and at far apexes with large coordinates; boxes behind the apex are culled (not vacuous).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "rayaccel/wide/beam_frustum.h"
#include "rayaccel/simd/dispatch.h"

namespace rayaccel {
namespace {

using wide::BeamFrustum;

/// The lane sets this CPU runs.
std::vector<simd::Isa> isas() {
  std::vector<simd::Isa> out = {simd::Isa::sse2};
  if (simd::best_isa(simd::Isa::avx2) == simd::Isa::avx2) out.push_back(simd::Isa::avx2);
  if (simd::best_isa() == simd::Isa::avx512) out.push_back(simd::Isa::avx512);
  return out;
}

/// The children of frustum_child_lanes() for `boxes` (at most 63, one bit each), on the lanes of `isa` (four-wide
/// nodes for SSE).
std::uint64_t kept_lanes(simd::Isa isa, const BeamFrustum& f, const std::vector<AABB>& boxes, float slack_scale) {
  std::uint64_t kept = 0;
  simd::run_with_lanes(isa, [&]<class Lanes>() RAYACCEL_LANE_LAMBDA {
    constexpr int W = Lanes::kWidth;
    for (std::size_t first = 0; first < boxes.size(); first += W) {
      wide::Node<W> node{};
      for (int lane = 0; lane < W; ++lane) {
        AABB box;  // empty unless a box is left
        if (first + lane < boxes.size()) box = boxes[first + lane];
        wide::set_child_bounds(node, lane, box);
      }
      kept |= std::uint64_t(wide::frustum_child_lanes<Lanes, W>(f, node, slack_scale)) << first;
    }
  });
  return kept;
}

struct RandomFrustum {
  BeamFrustum frustum;
  Vec3 corners[4];
};

/// A frustum of a camera-like tile at `apex`, `width` radians across, looking along a random axis.
RandomFrustum random_frustum(std::mt19937& rng, const Vec3& apex, float width) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const Vec3 axis = normalize(Vec3{u(rng), u(rng), u(rng)});
  const Vec3 a = normalize(cross(axis, std::fabs(axis.x) < 0.5f ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
  const Vec3 b = cross(axis, a);
  RandomFrustum out;
  const float su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
  for (int i = 0; i < 4; ++i) out.corners[i] = axis + a * (su[i] * width) + b * (sv[i] * width * 0.7f);
  out.frustum = BeamFrustum::through(apex, out.corners);
  return out;
}

TEST(BeamFrustum, BoxesTheBeamTouchesAreNeverCulled) {
  std::mt19937 rng(38);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (const simd::Isa isa : isas()) {
    int checked = 0, culled_off_beam = 0, off_beam = 0, held_rays = 0, lanes_proven = 0;
    for (const float scale : {1.0f, 1e3f, 1e6f, 3e8f}) {  // far apexes: coordinates up to 3e8
      // Apex and directions on one grid of g = 2^e, |apex| + |d| < 2^23 g: apex + d and apex - d are exact in float,
      // so the point box [apex + d, apex + d] lies exactly on the ray (no rounding slack in the test itself), and d
      // is within a few float roundings of the side planes often enough to need the margin.
      const float g = std::ldexp(1.0f, std::ilogb(scale) - 21);
      const auto on_grid = [&](double x) { return float(std::nearbyint(x / g)) * g; };
      for (int trial = 0; trial < 100; ++trial) {
        const Vec3 apex{on_grid(u(rng) * scale), on_grid(u(rng) * scale), on_grid(u(rng) * scale)};
        const RandomFrustum rf = random_frustum(rng, apex, 0.001f + 0.3f * float(unit(rng)));
        ASSERT_TRUE(rf.frustum.valid());
        std::vector<AABB> touching, away;
        for (int k = 0; k < 63; ++k) {  // at most 63 boxes: one bit each in a 64-bit mask
          // A direction on or near the beam's boundary (one or two weights zero or near it) or inside it.
          double w[4], sum = 0;
          for (double& x : w) sum += (x = unit(rng) * unit(rng) * unit(rng));
          const int edge = k % 5;
          if (edge < 4) w[edge] = 0.0, w[(edge + 1) % 4] *= (k & 8) ? 0.0 : 1e-7 * unit(rng);
          const double length = scale * (0.25 + 0.5 * unit(rng));
          Vec3 d;
          for (int c = 0; c < 3; ++c) {
            double v = 0;
            for (int i = 0; i < 4; ++i) v += w[i] * rf.corners[i][c];
            d[c] = on_grid(length * v / sum);
          }
          const Ray ray{apex, 0.0f, d, std::numeric_limits<float>::infinity()};
          // The float proof of the traversals is sufficient: never a ray holds() rejects, and nearly every ray well
          // inside (no weight set to zero or near it) that holds() accepts.
          const bool held = rf.frustum.holds(ray);
          int proven = 0;
          simd::run_with_lanes(isa, [&]<class Lanes>() RAYACCEL_LANE_LAMBDA {
            proven = wide::holds_lanes<Lanes>(rf.frustum, &ray, 1);
          });
          if (proven) {
            EXPECT_TRUE(held) << simd::to_string(isa) << ": the float proof held a ray outside";
          }
          if (!held) continue;
          if (edge == 4) {
            ++held_rays;
            lanes_proven += proven != 0;
          }
          const Vec3 p = apex + d, q = apex - d;  // exact; q lies behind the apex
          touching.push_back(AABB{p, p});
          away.push_back(AABB{q, q});
        }
        if (touching.empty()) continue;
        const std::uint64_t all = (std::uint64_t(1) << touching.size()) - 1;
        for (const float slack : {0.0f, BeamFrustum::kSlackScale}) {
          const std::uint64_t kept = kept_lanes(isa, rf.frustum, touching, slack);
          EXPECT_EQ(kept & all, all) << simd::to_string(isa) << " scale " << scale << " slack " << slack
                                     << ": a box on a ray of the beam was culled";
        }
        checked += int(touching.size());
        const std::uint64_t kept_away = kept_lanes(isa, rf.frustum, away, BeamFrustum::kSlackScale);
        // One box at a time (the other structures' nodes): the same answers as the lanes.
        const std::uint64_t kept_touching = kept_lanes(isa, rf.frustum, touching, BeamFrustum::kSlackScale);
        for (std::size_t i = 0; i < touching.size(); ++i) {
          EXPECT_EQ(rf.frustum.box_outside(touching[i]), !(kept_touching >> i & 1));
          EXPECT_EQ(rf.frustum.box_outside(away[i]), !(kept_away >> i & 1));
        }
        off_beam += int(away.size());
        culled_off_beam += int(away.size()) - __builtin_popcountll(kept_away & all);
      }
    }
    EXPECT_GT(checked, 4000) << simd::to_string(isa);
    EXPECT_GT(culled_off_beam, off_beam * 19 / 20) << simd::to_string(isa) << ": the culling test is vacuous";
    EXPECT_GT(held_rays, 1000) << simd::to_string(isa);
    EXPECT_GE(lanes_proven, held_rays * 99 / 100) << simd::to_string(isa) << ": the float proof is vacuous";
  }
}

TEST(BeamFrustum, HoldsOnlyRaysFromTheApexInsideEveryPlane) {
  const Vec3 corners[4] = {{-0.1f, -0.1f, -1}, {0.1f, -0.1f, -1}, {0.1f, 0.1f, -1}, {-0.1f, 0.1f, -1}};
  const BeamFrustum f = BeamFrustum::through({1, 2, 3}, corners);
  ASSERT_TRUE(f.valid());
  EXPECT_EQ(f.plane_count, 5);  // four sides and -z
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(f.holds({{1, 2, 3}, 0.0f, {0.05f, 0.0f, -1}, inf}));
  EXPECT_FALSE(f.holds({{1, 2, 3}, 0.0f, {0.2f, 0.0f, -1}, inf}));    // outside a side
  EXPECT_FALSE(f.holds({{1, 2, 3.5f}, 0.0f, {0.0f, 0.0f, -1}, inf}));  // another origin
  EXPECT_FALSE(f.holds({{1, 2, 3}, -1.0f, {0.0f, 0.0f, -1}, inf}));   // points behind the apex
  const Vec3 bad[4] = {{-0.1f, -0.1f, -1}, {inf, -0.1f, -1}, {0.1f, 0.1f, -1}, {-0.1f, 0.1f, -1}};
  EXPECT_FALSE(BeamFrustum::through({1, 2, 3}, bad).valid());
}

}  // namespace
}  // namespace rayaccel
