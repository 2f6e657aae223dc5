// Ray test of a capped convex hull (a box cut by up to eight planes): the robust slab test (Ize 2013) first, then
// each plane as the one-sided OBB slab (ray_obb.h), conservative in floating point, four planes at a time (SSE2).
#pragma once

#include <emmintrin.h>

#include <cmath>
#include <limits>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/geometry/ray_box.h"
#include "rayaccel/geometry/ray_obb.h"
#include "rayaccel/geometry/slab_interval.h"

namespace rayaccel {

/// Eight half-spaces {p : dot(normal[i], p - hull_reference_point(box)) <= offset[i]}, one per lane. A lane with a
/// zero normal and an infinite offset constrains nothing (the unused ones).
struct HullPlanes {
  static constexpr int kCount = 8;
  float normal_x[kCount];  ///< 32 bytes; normals are unit up to float rounding (the test is exact for the floats)
  float normal_y[kCount];  ///< 32 bytes
  float normal_z[kCount];  ///< 32 bytes
  float offset[kCount];    ///< 32 bytes

  Vec3 normal(int i) const { return {normal_x[i], normal_y[i], normal_z[i]}; }
};
static_assert(sizeof(HullPlanes) == 128);

/// The point the planes' offsets are measured from: the box's centre, computed without overflow; every caller
/// (fit and test) must use this one expression.
inline Vec3 hull_reference_point(const AABB& box) { return box.lo * 0.5f + box.hi * 0.5f; }

/// True when the segment [t_min, t_max] touches box ∩ planes; *t_entry gets the entry distance. Conservative: a ray
/// that touches the volume in exact arithmetic is never rejected (a ray missing the box is rejected before any plane
/// is looked at). Void rays and empty boxes never hit. The slack argument is the OBB's: a point of the volume lies
/// within reach (half the box's 1-norm extent) of the centre, so where the ray is inside, |t| |d| <= |o - c| + reach.
inline bool intersect_hull(const PreparedRay& r, const AABB& box, const HullPlanes& planes, float t_min, float t_max,
                           float* t_entry = nullptr) {
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
  const __m128 fx = _mm_set1_ps(f.x), fy = _mm_set1_ps(f.y), fz = _mm_set1_ps(f.z);
  const __m128 dx = _mm_set1_ps(r.direction.x), dy = _mm_set1_ps(r.direction.y), dz = _mm_set1_ps(r.direction.z);
  const __m128 pushed = _mm_set1_ps(slack);
  const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
  const __m128 float_max = _mm_set1_ps(std::numeric_limits<float>::max());
  const __m128 inf = _mm_set1_ps(std::numeric_limits<float>::infinity());
  __m128 enter = _mm_sub_ps(_mm_setzero_ps(), inf), leave = inf;
  for (int lane = 0; lane < HullPlanes::kCount; lane += 4) {
    const __m128 nx = _mm_loadu_ps(planes.normal_x + lane), ny = _mm_loadu_ps(planes.normal_y + lane),
                 nz = _mm_loadu_ps(planes.normal_z + lane);
    const __m128 o = _mm_add_ps(_mm_add_ps(_mm_mul_ps(nx, fx), _mm_mul_ps(ny, fy)), _mm_mul_ps(nz, fz));
    const __m128 d = _mm_add_ps(_mm_add_ps(_mm_mul_ps(nx, dx), _mm_mul_ps(ny, dy)), _mm_mul_ps(nz, dz));
    // Divided, not multiplied by 1/d, as in ray_obb.h. A negative d (or -0) makes t an entry bound, else an exit.
    const __m128 t = _mm_div_ps(_mm_sub_ps(_mm_add_ps(_mm_loadu_ps(planes.offset + lane), pushed), o), d);
    const __m128 negative = _mm_castsi128_ps(_mm_srai_epi32(_mm_castps_si128(d), 31));
    // A projection that overflowed (directions near FLT_MAX) would make t a false zero: such a lane is skipped.
    const __m128 usable = _mm_cmple_ps(_mm_and_ps(d, abs_mask), float_max);
    const __m128 as_entry = _mm_and_ps(usable, negative), as_exit = _mm_andnot_ps(negative, usable);
    // max/min return their second operand when either is NaN, so a NaN t (ray in the plane) constrains nothing.
    enter = _mm_max_ps(_mm_or_ps(_mm_and_ps(as_entry, t), _mm_andnot_ps(as_entry, _mm_sub_ps(_mm_setzero_ps(), inf))),
                       enter);
    leave = _mm_min_ps(_mm_or_ps(_mm_and_ps(as_exit, t), _mm_andnot_ps(as_exit, inf)), leave);
  }
  enter = _mm_max_ps(enter, _mm_shuffle_ps(enter, enter, _MM_SHUFFLE(1, 0, 3, 2)));
  enter = _mm_max_ps(enter, _mm_shuffle_ps(enter, enter, _MM_SHUFFLE(2, 3, 0, 1)));
  leave = _mm_min_ps(leave, _mm_shuffle_ps(leave, leave, _MM_SHUFFLE(1, 0, 3, 2)));
  leave = _mm_min_ps(leave, _mm_shuffle_ps(leave, leave, _MM_SHUFFLE(2, 3, 0, 1)));
  return clip_to_widened_slabs(_mm_cvtss_f32(enter), _mm_cvtss_f32(leave), t_near, t_far, t_entry);
}

}  // namespace rayaccel
