// Unit tests of the robust slab test (geometry/ray_box.h): signed-zero direction components with the origin
// inside, outside and exactly on a face plane, rays lying in faces, void rays, flat and empty boxes, and a
// randomized check that it never rejects a ray that touches the box in exact arithmetic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "../conformance/test_scenes.h"
#include "rayaccel/geometry/ray_box.h"
#include "../float_specials.h"

namespace rayaccel {
namespace {

using conformance::Rng;

using test_values::kInf;
const AABB kUnitBox(Vec3{0.0f}, Vec3{1.0f});

bool hits(const Ray& ray, const AABB& box, float* t_entry = nullptr) {
  const PreparedRay r(ray);
  return intersect_box(r, box, r.t_min, r.t_max, t_entry);
}

/// The direction with `axis` component `value` and the other two components +0 or -0 as `zero_bits` says.
Vec3 axis_direction(int axis, float value, int zero_bits) {
  Vec3 d;
  d[axis] = value;
  d[(axis + 1) % 3] = (zero_bits & 1) ? -0.0f : 0.0f;
  d[(axis + 2) % 3] = (zero_bits & 2) ? -0.0f : 0.0f;
  return d;
}

TEST(RayBox, SignedZeroComponentsFromOutside) {
  for (int bits = 0; bits < 4; ++bits) {
    const Vec3 d = axis_direction(0, 1.0f, bits);
    float t_entry = 0.0f;
    EXPECT_TRUE(hits(Ray{{-1.0f, 0.5f, 0.5f}, 0.0f, d, kInf}, kUnitBox, &t_entry)) << bits;
    // The entry distance is widened toward the ray by 2*gamma(3) (ray_box.h): conservative, and no looser.
    EXPECT_LE(t_entry, 1.0f);
    EXPECT_GE(t_entry, kSlabWidenDown);
    EXPECT_FALSE(hits(Ray{{-1.0f, 1.5f, 0.5f}, 0.0f, d, kInf}, kUnitBox)) << "parallel, above the box " << bits;
    EXPECT_FALSE(hits(Ray{{-1.0f, 0.5f, -0.5f}, 0.0f, d, kInf}, kUnitBox)) << "parallel, beside the box " << bits;
    EXPECT_FALSE(hits(Ray{{2.0f, 0.5f, 0.5f}, 0.0f, d, kInf}, kUnitBox)) << "box behind the origin " << bits;
    EXPECT_TRUE(hits(Ray{{2.0f, 0.5f, 0.5f}, 0.0f, axis_direction(0, -1.0f, bits), kInf}, kUnitBox)) << bits;
  }
}

TEST(RayBox, SignedZeroComponentsFromInside) {
  for (int axis = 0; axis < 3; ++axis) {
    for (int bits = 0; bits < 4; ++bits) {
      for (float sign : {1.0f, -1.0f}) {
        float t_entry = -1.0f;
        EXPECT_TRUE(hits(Ray{Vec3{0.5f}, 0.0f, axis_direction(axis, sign, bits), kInf}, kUnitBox, &t_entry));
        EXPECT_EQ(t_entry, 0.0f) << "entry distance is clipped to t_min";
      }
    }
  }
}

TEST(RayBox, OriginExactlyOnFacePlanes) {
  // The ray lies in the plane y = 1 (or y = 0): 0 * inf = NaN slab distances must not reject it.
  for (float y : {0.0f, 1.0f}) {
    for (int bits = 0; bits < 4; ++bits) {
      for (float sign : {1.0f, -1.0f}) {
        const Vec3 d = axis_direction(0, sign, bits);
        EXPECT_TRUE(hits(Ray{{sign > 0 ? -1.0f : 2.0f, y, 0.5f}, 0.0f, d, kInf}, kUnitBox)) << y << " " << bits;
        EXPECT_TRUE(hits(Ray{{0.5f, y, 0.5f}, 0.0f, d, kInf}, kUnitBox)) << "inside, on the face " << y;
        EXPECT_TRUE(hits(Ray{{sign > 0 ? -1.0f : 2.0f, y, 1.0f}, 0.0f, d, kInf}, kUnitBox)) << "along an edge";
      }
    }
  }
  // On the face plane of a face the ray leaves through: hit at t = 0 only.
  EXPECT_TRUE(hits(Ray{{1.0f, 0.5f, 0.5f}, 0.0f, {1.0f, 0.0f, 0.0f}, kInf}, kUnitBox));
  EXPECT_FALSE(hits(Ray{{1.0f, 0.5f, 0.5f}, 0.5f, {1.0f, 0.0f, 0.0f}, kInf}, kUnitBox));
}

TEST(RayBox, RayAlongAFace) {
  EXPECT_TRUE(hits(Ray{{0.5f, 1.0f, -1.0f}, 0.0f, {0.0f, -0.0f, 1.0f}, kInf}, kUnitBox));
  EXPECT_TRUE(hits(Ray{{-1.0f, 1.0f, -1.0f}, 0.0f, {1.0f, 0.0f, 1.0f}, kInf}, kUnitBox)) << "diagonal in the face";
  EXPECT_FALSE(hits(Ray{{0.5f, 1.0f, -1.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, 0.5f}, kUnitBox)) << "segment ends first";
}

TEST(RayBox, VoidRaysNeverHit) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const Ray& ray : {Ray{{nan, 0.5f, 0.5f}, 0.0f, {1, 0, 0}, kInf}, Ray{{-1, 0.5f, 0.5f}, 0.0f, {nan, 0, 0}, kInf},
                         Ray{{-1, 0.5f, 0.5f}, nan, {1, 0, 0}, kInf}, Ray{{-1, 0.5f, 0.5f}, 0.0f, {1, 0, 0}, nan},
                         Ray{{0.5f, 0.5f, 0.5f}, 0.0f, {0, 0, 0}, kInf}, Ray{{-kInf, 0.5f, 0.5f}, 0.0f, {1, 0, 0}, kInf},
                         Ray{{0.5f, 0.5f, 0.5f}, 0.0f, {kInf, 0, 0}, kInf}, Ray{{0.5f, 0.5f, 0.5f}, 2.0f, {1, 0, 0}, 1.0f}}) {
    EXPECT_FALSE(hits(ray, kUnitBox));
    EXPECT_FALSE(hits(ray, AABB(Vec3{-kInf}, Vec3{kInf}))) << "not even the infinite box";
  }
}

TEST(RayBox, FlatAndPointBoxes) {
  const AABB flat(Vec3{0.0f, 0.0f, 0.5f}, Vec3{1.0f, 1.0f, 0.5f});
  EXPECT_TRUE(hits(Ray{{0.5f, 0.5f, -1.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, kInf}, flat));
  EXPECT_TRUE(hits(Ray{{0.5f, 0.5f, 2.0f}, 0.0f, {-0.0f, 0.0f, -1.0f}, kInf}, flat));
  EXPECT_TRUE(hits(Ray{{-1.0f, 0.5f, 0.5f}, 0.0f, {1.0f, 0.0f, -0.0f}, kInf}, flat)) << "in the plane of the box";
  EXPECT_FALSE(hits(Ray{{-1.0f, 0.5f, 0.6f}, 0.0f, {1.0f, 0.0f, 0.0f}, kInf}, flat)) << "parallel above it";
  EXPECT_TRUE(hits(Ray{{0.2f, 0.3f, 0.0f}, 0.0f, {0.2f, 0.3f, 1.0f}, kInf}, flat)) << "oblique";
  const AABB point = AABB::of_point({0.25f, 0.5f, 0.75f});
  for (int axis = 0; axis < 3; ++axis) {
    for (int bits = 0; bits < 4; ++bits) {
      Vec3 o{0.25f, 0.5f, 0.75f};
      o[axis] -= 1.0f;
      EXPECT_TRUE(hits(Ray{o, 0.0f, axis_direction(axis, 1.0f, bits), kInf}, point)) << axis << " " << bits;
      o[(axis + 1) % 3] += 0.25f;
      EXPECT_FALSE(hits(Ray{o, 0.0f, axis_direction(axis, 1.0f, bits), kInf}, point)) << axis << " " << bits;
    }
  }
}

TEST(RayBox, EmptyBoxIsNeverHit) {
  Rng rng(1);
  for (int i = 0; i < 1000; ++i) {
    Vec3 d = rng.unit_vector();
    if (i % 4 == 0) d = axis_direction(i % 3, i % 8 < 4 ? 1.0f : -1.0f, i % 4);
    EXPECT_FALSE(hits(Ray{rng.in_box(kUnitBox), -kInf, d, kInf}, AABB::empty()));
  }
}

/// Exact-arithmetic stand-in: the slab test in double, whose rounding (~1e-16) is far below the float test's margin.
/// *entry receives the entry distance.
bool touches_in_double(const Ray& ray, const AABB& box, double* entry) {
  double t_near = ray.t_min, t_far = ray.t_max;
  for (int a = 0; a < 3; ++a) {
    const double o = ray.origin[a], d = ray.direction[a];
    if (d == 0.0) {
      if (o < box.lo[a] || o > box.hi[a]) return false;
      continue;
    }
    double t0 = (double(box.lo[a]) - o) / d, t1 = (double(box.hi[a]) - o) / d;
    if (t0 > t1) std::swap(t0, t1);
    t_near = std::max(t_near, t0);
    t_far = std::min(t_far, t1);
  }
  *entry = t_near;
  return t_near <= t_far;
}

TEST(RayBox, ConservativeOnRandomRaysThroughBoxes) {
  Rng rng(2);
  int touching = 0;
  constexpr int kTrials = 20000;
  for (int i = 0; i < kTrials; ++i) {
    const Vec3 a = rng.in_box(AABB(Vec3{-100.0f}, Vec3{100.0f}));
    Vec3 b = a + rng.in_box(AABB(Vec3{0.0f}, Vec3{rng.uniform(1e-3f, 50.0f)}));
    if (i % 10 == 0) {  // sometimes flat
      const std::uint32_t axis = rng.below(3);
      b[axis] = a[axis];
    }
    const AABB box(min(a, b), max(a, b));
    // A target inside the box, sometimes snapped onto a face, edge or corner.
    Vec3 p = rng.in_box(box);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t snap = rng.below(6);
      if (snap == 0) p[k] = box.lo[k];
      if (snap == 1) p[k] = box.hi[k];
    }
    const Vec3 o = rng.below(3) == 0 ? rng.in_box(box) : p + rng.unit_vector() * rng.uniform(0.1f, 300.0f);
    Ray ray{o, 0.0f, p - o, rng.below(2) ? kInf : 1.0f};
    if (ray.direction == Vec3{}) continue;
    if (rng.below(5) == 0) ray.direction[rng.below(3)] = rng.below(2) ? 0.0f : -0.0f;  // may now miss: fine
    double entry = 0.0;
    if (!touches_in_double(ray, box, &entry)) continue;
    ++touching;
    float t_entry = 0.0f;
    ASSERT_TRUE(hits(ray, box, &t_entry)) << "rejected a touching ray: box (" << box.lo.x << "," << box.lo.y << "," << box.lo.z
                                << ")-(" << box.hi.x << "," << box.hi.y << "," << box.hi.z << ") origin (" << o.x
                                << "," << o.y << "," << o.z << ") dir (" << ray.direction.x << ","
                                << ray.direction.y << "," << ray.direction.z << ") t_max " << ray.t_max;
  }
  EXPECT_GT(touching, kTrials / 2) << "the sampling should mostly produce touching rays";
}

}  // namespace
}  // namespace rayaccel
