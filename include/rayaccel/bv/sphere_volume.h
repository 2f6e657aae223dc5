// Bounding sphere as a BVH volume: fitted by Larsson's EPOS-26 ("Fast and Tight Fitting Bounding Spheres", SIGRAD
// 2008: the exact minimum sphere of the extremal points on 13 directions, then Ritter's growth pass over all
// points), or exactly by Welzl's move-to-front algorithm for small sets. Ray test: ray_sphere_interval.
#pragma once

#include <cmath>
#include <limits>
#include <numbers>
#include <span>

#include "rayaccel/bv/bounding_volume.h"
#include "rayaccel/geometry/ray_sphere.h"
#include "rayaccel/geometry/slab_interval.h"

namespace rayaccel {

struct SphereVolume {
  static constexpr const char* kName = "sphere";
  /// Sets of at most this many points get the exact minimum enclosing sphere (Welzl); larger ones EPOS-26.
  static constexpr std::size_t kExactFitMaxPoints = 32;
  struct RayContext {
    const PreparedRay* ray;
  };

  Vec3 center;
  float radius = -1.0f;  ///< negative: the empty sphere

  static RayContext prepare(const PreparedRay& ray) { return {&ray}; }
  /// Encloses every point exactly (radius measured in double from the stored float center, rounded up); the ray
  /// test's slack, not a fit margin, absorbs rounding. Empty span -> empty sphere.
  static SphereVolume fit(std::span<const Vec3> points);

  /// Conservative: the radius grows by kRayOriginSlack of the origin's distance, which dwarfs the double-precision
  /// error of the interval, and the interval is widened like the slab tests', so a ray that touches the fitted
  /// points' hull in [t_min, t_max] is never rejected. The widening is done in double (origin and center up to
  /// 2 * FLT_MAX apart), and a radius beyond float's range (infinite: points more than FLT_MAX apart) holds every
  /// ray's whole segment. Void rays and the empty sphere never hit.
  bool intersect(const RayContext& c, float t_min, float t_max, float* t_entry) const {
    if (!(radius >= 0.0f)) return false;
    constexpr float kInf = std::numeric_limits<float>::infinity();
    if (radius == kInf) return clip_to_widened_slabs(-kInf, kInf, t_min, t_max, t_entry);
    const Vec3& o = c.ray->origin;
    const double slack = double(kRayOriginSlack) * (std::fabs(double(o.x) - center.x) +
                                                    std::fabs(double(o.y) - center.y) +
                                                    std::fabs(double(o.z) - center.z));
    double t0, t1;
    if (!ray_sphere_interval(*c.ray, center, double(radius) + slack, t0, t1)) return false;
    return clip_to_widened_slabs(static_cast<float>(t0), static_cast<float>(t1), t_min, t_max, t_entry);
  }
  float surface_area() const { return radius >= 0.0f ? 4.0f * std::numbers::pi_v<float> * radius * radius : 0.0f; }
  float volume() const {
    return radius >= 0.0f ? 4.0f / 3.0f * std::numbers::pi_v<float> * radius * radius * radius : 0.0f;
  }
  /// The box [center - radius, center + radius], rounded outward.
  AABB bounds() const;
  /// |p - center| <= radius, evaluated in double with a tolerance of a few float ulps.
  bool contains(const Vec3& p) const;
};
static_assert(BoundingVolume<SphereVolume>);

}  // namespace rayaccel
