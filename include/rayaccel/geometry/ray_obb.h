// Ray/oriented-box test: the ray carried into the box frame and clipped by its three slabs as in the robust AABB
// test (Ize 2013), widened by a bound on the transform's rounding (pbrt 3.9 style), so conservative.
#pragma once

#include <cmath>
#include <limits>

#include "rayaccel/core/ray.h"
#include "rayaccel/geometry/slab_interval.h"

namespace rayaccel {

/// An oriented box: the points p with |dot(axis[i], p - center)| <= half[i] for i = 0..2. The axes are unit and
/// orthogonal up to float rounding (the test is exact for the box the stored floats define). half.x < 0 marks an
/// empty box that no ray hits.
struct Obb {
  Vec3 axis[3];  ///< 36 bytes: rows of the world-to-box rotation
  Vec3 center;   ///< 12 bytes
  Vec3 half;     ///< 12 bytes: half extents along each axis
  float reach;   ///<  4 bytes: half.x + half.y + half.z, a bound on the center-to-corner distance
};
static_assert(sizeof(Obb) == 64, "an OBB is one cache line");

/// Relative bound on the frame transform's error, as a multiple of the distance scale |o - c|_1 + reach: the
/// transformed origin is off by at most gamma(5) of |o - c|_1 and the transformed direction by gamma(3) of |d|, and
/// within the box |t| |d| <= |o - c| + reach; 4x slack on top covers the non-unit rounding of the stored axes.
inline constexpr float kObbFrameSlack = 4.0f * (5.0f + 3.0f) * 0x1p-24f;

/// True when the segment [t_min, t_max] of the ray touches the box; *t_entry gets the entry distance. Conservative:
/// a ray that touches the box in exact arithmetic is never rejected. Void rays and empty boxes never hit.
inline bool intersect_obb(const PreparedRay& r, const Obb& box, float t_min, float t_max, float* t_entry = nullptr) {
  if (!(box.half.x >= 0.0f)) return false;
  const Vec3 f = r.origin - box.center;
  const float slack = kObbFrameSlack * (std::fabs(f.x) + std::fabs(f.y) + std::fabs(f.z) + box.reach);
  float enter = -std::numeric_limits<float>::infinity(), leave = std::numeric_limits<float>::infinity();
  for (int a = 0; a < 3; ++a) {
    const float o = dot(box.axis[a], f);
    const float d = dot(box.axis[a], r.direction);
    const float extent = box.half[a] + slack;
    // Entry plane first: for d = -0 the sign bit still picks the correct side, as in ray_box.h. Divided rather
    // than multiplied by 1/d: d can be far smaller than the ray's components (a tiny direction almost
    // perpendicular to the axis), where 1/d would overflow although the distances themselves are finite.
    const float near_plane = std::signbit(d) ? extent : -extent;
    const float t0 = (near_plane - o) / d;
    const float t1 = (-near_plane - o) / d;
    enter = t0 > enter ? t0 : enter;
    leave = t1 < leave ? t1 : leave;
  }
  return clip_to_widened_slabs(enter, leave, t_min, t_max, t_entry);
}

}  // namespace rayaccel
