// Ray test of a capped convex hull: a box cut by a few arbitrary planes. The box is clipped first by the robust slab
// test (ray_box.h, Ize 2013), which also makes it the cheap first filter; each plane is then the one-sided form of
// the OBB's slab test (ray_obb.h): the ray carried onto the plane's normal relative to the box centre, the plane
// pushed out by the same bound on that transform's rounding, so the test is conservative in floating point.
#pragma once

#include <cmath>
#include <limits>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/geometry/ray_box.h"
#include "rayaccel/geometry/ray_obb.h"
#include "rayaccel/geometry/slab_interval.h"

namespace rayaccel {

/// A half-space {p : dot(normal, p - hull_reference_point(box)) <= offset} of a capped hull. A zero normal with an
/// infinite offset constrains nothing.
struct HullPlane {
  Vec3 normal;   ///< 12 bytes: unit up to float rounding (the test is exact for the stored floats)
  float offset;  ///<  4 bytes
};
static_assert(sizeof(HullPlane) == 16);

/// The point the planes' offsets are measured from: the box's centre, computed without overflow; every caller
/// (fit and test) must use this one expression.
inline Vec3 hull_reference_point(const AABB& box) { return box.lo * 0.5f + box.hi * 0.5f; }

/// True when the segment [t_min, t_max] touches box ∩ planes; *t_entry gets the entry distance. Conservative: a ray
/// that touches the volume in exact arithmetic is never rejected (a ray missing the box is rejected before any plane
/// is looked at). Void rays and empty boxes never hit. The slack argument is the OBB's: a point of the volume lies
/// within reach (half the box's 1-norm extent) of the centre, so where the ray is inside, |t| |d| <= |o - c| + reach.
inline bool intersect_hull(const PreparedRay& r, const AABB& box, const HullPlane* planes, int plane_count,
                           float t_min, float t_max, float* t_entry = nullptr) {
  float t_near = t_min, t_far = t_max;
  if (!clip_ray_to_box(r, box, t_near, t_far)) {
    if (t_entry) *t_entry = t_near;
    return false;
  }
  const Vec3 c = hull_reference_point(box);
  const Vec3 f = r.origin - c;
  const Vec3 extent = box.hi - box.lo;
  const float reach = 0.5f * (extent.x + extent.y + extent.z);
  const float slack = kObbFrameSlack * (std::fabs(f.x) + std::fabs(f.y) + std::fabs(f.z) + reach);
  float enter = -std::numeric_limits<float>::infinity(), leave = std::numeric_limits<float>::infinity();
  for (int i = 0; i < plane_count; ++i) {
    const HullPlane& p = planes[i];
    const float o = dot(p.normal, f);
    const float d = dot(p.normal, r.direction);
    // A projection that overflowed (directions near FLT_MAX) would make t a false zero: such a plane is skipped.
    if (!(std::fabs(d) <= std::numeric_limits<float>::max())) continue;
    // Divided, not multiplied by 1/d, as in ray_obb.h. d < 0 (or -0): the ray enters the half-space, t is an entry
    // bound; otherwise it leaves it. A NaN (ray in the plane, or an overflowed slack) constrains nothing.
    const float t = (p.offset + slack - o) / d;
    if (std::signbit(d)) {
      enter = t > enter ? t : enter;
    } else {
      leave = t < leave ? t : leave;
    }
  }
  return clip_to_widened_slabs(enter, leave, t_near, t_far, t_entry);
}

}  // namespace rayaccel
