// Capsule (swept sphere) as a BVH volume (Larsen et al. 1999): fitted over candidate axes and a few radii, least
// surface area winning. Ray test: ray_capsule_interval (geometry/ray_capsule.h).
#pragma once

#include <cmath>
#include <limits>
#include <numbers>
#include <span>

#include "rayaccel/bv/bounding_volume.h"
#include "rayaccel/geometry/ray_capsule.h"
#include "rayaccel/geometry/slab_interval.h"

namespace rayaccel {

struct CapsuleVolume {
  static constexpr const char* kName = "capsule";
  struct RayContext {
    const PreparedRay* ray;
  };

  Vec3 a;                ///< 12 bytes: one end of the axis segment
  Vec3 b;                ///< 12 bytes: the other end (== a for a sphere)
  float radius = -1.0f;  ///<  4 bytes: negative: the empty capsule

  static RayContext prepare(const PreparedRay& ray) { return {&ray}; }
  /// Encloses every point exactly (radius measured in double from the stored float segment, rounded up); the ray
  /// test's slack, not a fit margin, absorbs rounding. Empty span -> empty capsule.
  static CapsuleVolume fit(std::span<const Vec3> points);

  /// Conservative like SphereVolume::intersect: the radius grows by kRayOriginSlack of the origin's distance from
  /// a plus the capsule's own size, the interval is computed in double and widened like the slab tests'. A radius
  /// beyond float's range holds every ray's whole segment. Void rays and the empty capsule never hit.
  bool intersect(const RayContext& c, float t_min, float t_max, float* t_entry) const {
    if (!(radius >= 0.0f)) return false;
    constexpr float kInf = std::numeric_limits<float>::infinity();
    if (radius == kInf) return clip_to_widened_slabs(-kInf, kInf, t_min, t_max, t_entry);
    const Vec3& o = c.ray->origin;
    const double slack =
        double(kRayOriginSlack) *
        (std::fabs(double(o.x) - a.x) + std::fabs(double(o.y) - a.y) + std::fabs(double(o.z) - a.z) +
         std::fabs(double(b.x) - a.x) + std::fabs(double(b.y) - a.y) + std::fabs(double(b.z) - a.z) + radius);
    double t0, t1;
    if (!ray_capsule_interval(*c.ray, a, b, double(radius) + slack, t0, t1)) return false;
    return clip_to_widened_slabs(static_cast<float>(t0), static_cast<float>(t1), t_min, t_max, t_entry);
  }
  /// Length of the axis segment, in double.
  double segment_length() const;
  float surface_area() const {
    if (!(radius >= 0.0f)) return 0.0f;
    const double r = radius;
    return static_cast<float>(2.0 * std::numbers::pi * r * segment_length() + 4.0 * std::numbers::pi * r * r);
  }
  float volume() const {
    if (!(radius >= 0.0f)) return 0.0f;
    const double r = radius;
    return static_cast<float>(std::numbers::pi * r * r * (segment_length() + 4.0 / 3.0 * r));
  }
  /// The box of both end spheres, rounded outward.
  AABB bounds() const;
  /// Distance from p to the segment <= radius, in double with a tolerance of a few float ulps.
  bool contains(const Vec3& p) const;
};
static_assert(BoundingVolume<CapsuleVolume>);

}  // namespace rayaccel
