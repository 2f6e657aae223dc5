// Oriented bounding box as a BVH volume. Fit: the smallest-area box among the AABB, the PCA frame (covariance
// eigenvectors by Jacobi rotations) and the DiTO-26 candidate frames of Larsson & Kallberg 2011 ("Fast Computation of
// Tight-Fitting Oriented Bounding Boxes", Game Engine Gems 2). Ray test: intersect_obb (geometry/ray_obb.h).
#pragma once

#include <span>

#include "rayaccel/bv/bounding_volume.h"
#include "rayaccel/geometry/ray_obb.h"

namespace rayaccel {

struct ObbVolume {
  static constexpr const char* kName = "obb";
  struct RayContext {
    const PreparedRay* ray;
  };

  Obb box{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {}, {-1, -1, -1}, 0.0f};  ///< empty until fitted

  static RayContext prepare(const PreparedRay& ray) { return {&ray}; }
  /// Encloses every point exactly (extents computed in double for the stored float axes and center, rounded up);
  /// the ray test's slack, not a fit margin, absorbs rounding. Empty span -> empty box.
  static ObbVolume fit(std::span<const Vec3> points);
  /// The box with the given (orthonormal) axes enclosing the points, for callers with their own frame; the axes are
  /// re-orthonormalized in double first.
  static ObbVolume fit_with_axes(std::span<const Vec3> points, const Vec3& axis0, const Vec3& axis1);

  bool intersect(const RayContext& c, float t_min, float t_max, float* t_entry) const {
    return intersect_obb(*c.ray, box, t_min, t_max, t_entry);
  }
  bool is_empty() const { return !(box.half.x >= 0.0f); }
  float surface_area() const {
    if (is_empty()) return 0.0f;
    const Vec3& h = box.half;
    return 8.0f * (h.x * h.y + h.y * h.z + h.z * h.x);
  }
  float volume() const { return is_empty() ? 0.0f : 8.0f * box.half.x * box.half.y * box.half.z; }
  /// The axis-aligned box around the eight corners, rounded outward.
  AABB bounds() const;
  /// |dot(axis[i], p - center)| <= half[i] for all i, in double with a tolerance of a few float ulps.
  bool contains(const Vec3& p) const;
};
static_assert(BoundingVolume<ObbVolume>);

}  // namespace rayaccel
