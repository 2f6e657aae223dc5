// Unit tests of PreparedRay (which rays are void, reciprocal directions and signs of +-0, the watertight axis
// permutation) and of Hit's tracing bound (begin / finish).
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "../float_specials.h"

namespace rayaccel {
namespace {

using test_values::kInf;
using test_values::kNaN;

TEST(PreparedRay, ValidRaysKeepTheirInterval) {
  const PreparedRay r(Ray{{1, 2, 3}, 0.5f, {0, 0, 1}, 8.0f});
  EXPECT_FALSE(r.is_void());
  EXPECT_EQ(r.t_min, 0.5f);
  EXPECT_EQ(r.t_max, 8.0f);
  EXPECT_FALSE(PreparedRay(Ray{{0, 0, 0}, 2.0f, {1, 0, 0}, 2.0f}).is_void()) << "t_min == t_max is allowed";
  EXPECT_FALSE(PreparedRay(Ray{{0, 0, 0}, 0.0f, {1, 0, 0}, 0.0f}).is_void());
  EXPECT_FALSE(PreparedRay(Ray{{0, 0, 0}, -kInf, {1, 0, 0}, kInf}).is_void());
  EXPECT_FALSE(PreparedRay(Ray{{0, 0, 0}, kInf, {1, 0, 0}, kInf}).is_void());
  EXPECT_FALSE(PreparedRay(Ray{{0, 0, 0}, 0.0f, {FLT_MIN, 0, 0}, kInf}).is_void()) << "the smallest normal length";
}

TEST(PreparedRay, SubnormalDirectionComponentsReadAsZero) {
  // Their reciprocals overflow float, so box tests can follow such a ray only as if they were zero; the triangle test
  // follows the same ray (the fuzz input tests/fuzz/corpus/fuzz_differential/subnormal-direction-component).
  const PreparedRay r(Ray{{0, 0, 0}, 0.0f, {1e-40f, -0.25f, -7.0e6f}, kInf});
  EXPECT_EQ(r.direction.x, 0.0f);
  EXPECT_FALSE(std::signbit(r.direction.x));
  EXPECT_EQ(r.inv_direction.x, kInf);
  EXPECT_EQ(r.kz, 2);
  EXPECT_EQ(r.ky, 0) << "z negative swaps kx and ky";
  EXPECT_EQ(r.shear_y, 0.0f) << "the flushed component shears by exactly zero";
  const PreparedRay n(Ray{{0, 0, 0}, 0.0f, {1.0f, -1e-39f, 0.0f}, kInf});
  EXPECT_EQ(n.direction.y, 0.0f);
  EXPECT_TRUE(std::signbit(n.direction.y)) << "the sign is kept, so the near plane is the same";
  EXPECT_EQ(n.inv_direction.y, -kInf);
  EXPECT_EQ(n.negative[1], 1);
  EXPECT_EQ(n.direction.x, 1.0f);
  // A direction of subnormal components only reads as zero: void, for the cheap check too.
  const float tiniest = std::numeric_limits<float>::denorm_min();
  for (const Vec3& d : {Vec3{1e-40f, 0, 0}, Vec3{1e-38f, -1e-38f, 1e-38f}, Vec3{0, 0, -tiniest}}) {
    const Ray ray{{1, 2, 3}, 0.0f, d, kInf};
    EXPECT_TRUE(PreparedRay(ray).is_void());
    EXPECT_FALSE(is_valid_ray(ray));
  }
}

TEST(PreparedRay, BadRaysAreVoid) {
  const Vec3 o{1, 2, 3}, d{0.5f, -0.5f, 1.0f};
  std::vector<Ray> bad{Ray{o, 0.0f, {0, 0, 0}, kInf}, Ray{o, 0.0f, {-0.0f, 0.0f, -0.0f}, kInf},
                       Ray{o, kNaN, d, kInf},          Ray{o, 0.0f, d, kNaN},
                       Ray{o, 3.0f, d, 2.0f},          Ray{o, kInf, d, -kInf}};
  for (int a = 0; a < 3; ++a) {
    for (float v : {kNaN, kInf, -kInf}) {
      Ray ro{o, 0.0f, d, kInf}, rd{o, 0.0f, d, kInf};
      ro.origin[a] = v;
      rd.direction[a] = v;
      bad.push_back(ro);
      bad.push_back(rd);
    }
  }
  for (const Ray& ray : bad) {
    const PreparedRay r(ray);
    EXPECT_TRUE(r.is_void());
    EXPECT_FALSE(is_valid_ray(ray)) << "the cheap check (used by the Embree wrapper) follows the same rule";
    EXPECT_EQ(r.t_min, kInf);
    EXPECT_EQ(r.t_max, -kInf);
  }
  for (const Ray& ray : {Ray{o, 0.0f, d, kInf}, Ray{o, 2.0f, d, 2.0f}, Ray{o, -kInf, {0, 0, -1e-30f}, kInf}}) {
    EXPECT_TRUE(is_valid_ray(ray));
    EXPECT_FALSE(PreparedRay(ray).is_void());
  }
}

TEST(PreparedRay, ReciprocalKeepsTheSignOfZero) {
  const PreparedRay r(Ray{{0, 0, 0}, 0.0f, {0.0f, -0.0f, -2.0f}, kInf});
  EXPECT_EQ(r.inv_direction.x, kInf);
  EXPECT_EQ(r.inv_direction.y, -kInf);
  EXPECT_EQ(r.inv_direction.z, -0.5f);
  EXPECT_EQ(r.negative[0], 0);
  EXPECT_EQ(r.negative[1], 1) << "-0 counts as negative";
  EXPECT_EQ(r.negative[2], 1);
}

TEST(PreparedRay, ShearAxesFollowTheDominantComponent) {
  const PreparedRay up(Ray{{0, 0, 0}, 0.0f, {0.1f, 3.0f, -0.2f}, kInf});
  EXPECT_EQ(up.kz, 1);
  EXPECT_EQ(up.kx, 2);
  EXPECT_EQ(up.ky, 0);
  EXPECT_FLOAT_EQ(up.shear_z, 1.0f / 3.0f);
  const PreparedRay down(Ray{{0, 0, 0}, 0.0f, {0.1f, -3.0f, -0.2f}, kInf});
  EXPECT_EQ(down.kz, 1);
  EXPECT_EQ(down.kx, 0) << "a negative dominant component swaps kx and ky to keep the winding";
  EXPECT_EQ(down.ky, 2);
  for (const Vec3& d : {Vec3{1, 1, 1}, Vec3{-2, 2, 0}, Vec3{0, 0, -1}}) {
    const PreparedRay r(Ray{{0, 0, 0}, 0.0f, d, kInf});
    EXPECT_EQ(r.kx + r.ky + r.kz, 3) << "a permutation of the axes";
    EXPECT_EQ(std::fabs(d[r.kz]), std::fmax(std::fabs(d.x), std::fmax(std::fabs(d.y), std::fabs(d.z))));
  }
}

/// The watertight test's axes and shear as Woop et al. define them, written out independently of PreparedRay (so a
/// faster form of its set-up must keep every bit): kz the dominant axis (ties to the lower one), kx and ky the next two
/// in cyclic order, swapped when d[kz] < 0, shear constants d[kx] / d[kz], d[ky] / d[kz], 1 / d[kz].
struct ReferenceShear {
  int kx, ky, kz;
  float shear_x, shear_y, shear_z;
  explicit ReferenceShear(const Vec3& d) {
    const Vec3 ad{std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)};
    kz = (ad.x >= ad.y && ad.x >= ad.z) ? 0 : (ad.y >= ad.z ? 1 : 2);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (d[kz] < 0.0f) std::swap(kx, ky);
    const float dz = d[kz] != 0.0f ? d[kz] : 1.0f;
    shear_x = d[kx] / dz;
    shear_y = d[ky] / dz;
    shear_z = 1.0f / dz;
  }
};

TEST(PreparedRay, ShearSetUpMatchesTheDefinitionBitForBit) {
  // Every combination of signs, ties between components, zeros of both signs, tiny and huge magnitudes, and NaN.
  const float magnitudes[] = {0.0f, 1e-40f, 0.25f, 1.0f, 3.0f, 1e30f, kInf, kNaN};
  std::mt19937 random(7);
  std::uniform_real_distribution<float> uniform(-4.0f, 4.0f);
  std::vector<Vec3> directions;
  for (float a : magnitudes) {
    for (float b : magnitudes) {
      for (float c : magnitudes) {
        for (int signs = 0; signs < 8; ++signs) {
          directions.push_back({signs & 1 ? -a : a, signs & 2 ? -b : b, signs & 4 ? -c : c});
        }
      }
    }
  }
  for (int i = 0; i < 20000; ++i) directions.push_back({uniform(random), uniform(random), uniform(random)});
  const auto same_bits = [](float x, float y) { return std::memcmp(&x, &y, sizeof(float)) == 0; };
  for (const Vec3& d : directions) {
    const PreparedRay r(Ray{{0, 0, 0}, 0.0f, d, kInf});
    const ReferenceShear want(readable_direction(d));  // the direction as kernels read it (subnormals are zero)
    ASSERT_EQ(r.kz, want.kz) << d.x << " " << d.y << " " << d.z;
    ASSERT_EQ(r.kx, want.kx) << d.x << " " << d.y << " " << d.z;
    ASSERT_EQ(r.ky, want.ky) << d.x << " " << d.y << " " << d.z;
    ASSERT_TRUE(same_bits(r.shear_x, want.shear_x)) << d.x << " " << d.y << " " << d.z;
    ASSERT_TRUE(same_bits(r.shear_y, want.shear_y)) << d.x << " " << d.y << " " << d.z;
    ASSERT_TRUE(same_bits(r.shear_z, want.shear_z)) << d.x << " " << d.y << " " << d.z;
  }
}

TEST(HitRecord, BeginSetsAnExclusiveBoundJustAboveTMax) {
  const PreparedRay r(Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, 2.0f});
  const Hit h = Hit::begin(r);
  EXPECT_GT(h.t, 2.0f);
  EXPECT_EQ(h.t, std::nextafter(2.0f, kInf));
  EXPECT_FALSE(h.found());
  EXPECT_EQ(Hit::begin(PreparedRay(Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, kInf})).t, kInf);
}

TEST(HitRecord, FinishNormalisesMisses) {
  Hit miss;
  miss.t = 3.0f;
  miss.u = 0.5f;
  miss.finish();
  EXPECT_EQ(miss.t, kInf);
  EXPECT_EQ(miss.u, 0.0f);
  EXPECT_EQ(miss.v, 0.0f);
  Hit hit;
  hit.t = 3.0f;
  hit.prim_id = 4;
  hit.u = 0.25f;
  hit.finish();
  EXPECT_EQ(hit.t, 3.0f);
  EXPECT_EQ(hit.u, 0.25f);
}

}  // namespace
}  // namespace rayaccel
