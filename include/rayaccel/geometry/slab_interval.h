// The last step of the slab tests of oriented volumes (OBB, k-DOP): widen the combined slab interval by the
// AABB test's rounding bound (Ize 2013, constants from ray_box.h) and clip the ray's segment to it.
#pragma once

#include "rayaccel/geometry/ray_box.h"

namespace rayaccel {

/// Positional slack of the oriented volumes' ray tests, relative to the ray origin's distance from the volume: 4
/// float ulps. The watertight triangle test rounds (shears) its vertices relative to the ray origin by about this
/// much, so it can report a hit a few ulps of |v - o| outside the exact triangle; the slack keeps such hits inside.
inline constexpr float kRayOriginSlack = 0x1p-22f;

/// Clips [t_min, t_max] to the slab interval [enter, leave] after widening both ends by 2*gamma(3) (the entry
/// toward -inf, the exit toward +inf), so rounding in the slab distances never rejects a touching ray and the entry
/// never lies beyond a hit on the fitted geometry. Shared by the k-DOP and OBB tests.
inline bool clip_to_widened_slabs(float enter, float leave, float t_min, float t_max, float* t_entry) {
  enter *= enter >= 0.0f ? kSlabWidenDown : kSlabWidenUp;
  leave *= leave >= 0.0f ? kSlabWidenUp : kSlabWidenDown;
  const float t_near = enter > t_min ? enter : t_min;
  const float t_far = leave < t_max ? leave : t_max;
  if (t_entry) *t_entry = t_near;
  return t_near <= t_far;
}

}  // namespace rayaccel
