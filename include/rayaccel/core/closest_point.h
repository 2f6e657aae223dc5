// ClosestPoint: the answer of a closest-point query, also the 28-byte record of the .closest file.
#pragma once

#include <cstdint>
#include <limits>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/vec3.h"

namespace rayaccel {

/// The closest point of the scene to a query point, the triangle it lies on, its barycentrics there (point =
/// (1-u-v) v0 + u v1 + v v2) and the distance. Nothing within the search radius: prim_id == kInvalidPrimId,
/// distance = +inf, the rest 0.
struct ClosestPoint {
  Vec3 point;
  float distance = std::numeric_limits<float>::infinity();
  std::uint32_t prim_id = kInvalidPrimId;
  float u = 0.0f;
  float v = 0.0f;
  bool found() const { return prim_id != kInvalidPrimId; }
  // Field order matches the record of the .closest file: x y z distance prim_id u v.
};
static_assert(sizeof(ClosestPoint) == 28, "ClosestPoint is the 28-byte record of the .closest file");

}  // namespace rayaccel
