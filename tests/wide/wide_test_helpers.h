// Helpers of the wide BVH tests: an accelerator's build statistics by name, and a check that two accelerators over the
// same scene give bit-identical closest hits and the same any-hit answers on seeded rays between random points of the
// scene box.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <string>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel::wide {

/// build_statistics() as a map from name to value.
inline std::map<std::string, double> statistics(const Accelerator& accel) {
  std::map<std::string, double> out;
  for (const auto& s : accel.build_statistics()) out[s.name] = s.value;
  return out;
}

/// Expects a and b to agree bit for bit on `count` rays (every third one a segment of half its length); returns how
/// many rays hit, so callers can check the rays were not all misses.
inline int expect_same_answers(const Scene& scene, const Accelerator& a, const Accelerator& b, int count,
                               unsigned seed) {
  const AABB box = scene.bounds();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  auto inside = [&] {
    return Vec3{box.lo.x + u(rng) * (box.hi.x - box.lo.x), box.lo.y + u(rng) * (box.hi.y - box.lo.y),
                box.lo.z + u(rng) * (box.hi.z - box.lo.z)};
  };
  int hits = 0;
  for (int i = 0; i < count; ++i) {
    const Vec3 origin = inside();
    const Ray ray{origin, 0.0f, inside() - origin, i % 3 == 0 ? 0.5f : std::numeric_limits<float>::infinity()};
    const Hit ha = a.intersect(ray);
    const Hit hb = b.intersect(ray);
    EXPECT_EQ(ha.prim_id, hb.prim_id) << "ray " << i;
    EXPECT_EQ(std::memcmp(&ha.t, &hb.t, sizeof ha.t), 0) << "ray " << i;
    EXPECT_EQ(std::memcmp(&ha.u, &hb.u, sizeof ha.u), 0) << "ray " << i;
    EXPECT_EQ(std::memcmp(&ha.v, &hb.v, sizeof ha.v), 0) << "ray " << i;
    EXPECT_EQ(a.occluded(ray), b.occluded(ray)) << "ray " << i;
    if (::testing::Test::HasFailure()) return hits;
    hits += ha.prim_id != kInvalidPrimId ? 1 : 0;
  }
  return hits;
}

}  // namespace rayaccel::wide
