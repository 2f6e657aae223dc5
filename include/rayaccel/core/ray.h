// Ray {origin, direction, t_min, t_max} and PreparedRay, the per-ray constants traversal computes once:
// reciprocal direction and signs for the slab test (Ize 2013), shear constants for the watertight triangle test
// (Woop, Benthin, Wald 2013).
#pragma once

#include <cmath>
#include <limits>

#include "rayaccel/core/vec3.h"

namespace rayaccel {

/// A ray; the direction need not be normalized and t is measured in units of its length.
struct Ray {
  Vec3 origin;
  float t_min = 0.0f;
  Vec3 direction{0.0f, 0.0f, 1.0f};
  float t_max = std::numeric_limits<float>::infinity();
  // Field order matches the 32-byte record of the .rays file: ox oy oz tmin dx dy dz tmax.
};
static_assert(sizeof(Ray) == 32, "Ray is the 32-byte record of the .rays file");

/// A direction component as every kernel reads it: subnormal components (0 < |d| < FLT_MIN) read as zero of the same
/// sign, as under the CPU's denormals-are-zero mode. Their reciprocals overflow float, so a box test could only follow
/// such a ray as if the component were zero; the triangle test, its exact fallback and every structure follow that
/// same ray, so all of them agree. The ray followed differs from the one given by less than FLT_MIN * |t| in that
/// coordinate.
inline float readable_direction(float d) {
  return std::fabs(d) < std::numeric_limits<float>::min() ? std::copysign(0.0f, d) : d;
}
inline Vec3 readable_direction(const Vec3& d) {
  return {readable_direction(d.x), readable_direction(d.y), readable_direction(d.z)};
}

/// False for a "void" ray (see PreparedRay): a NaN or infinite origin or direction component, a zero direction
/// (every component zero or subnormal: see readable_direction()), a NaN t bound, or t_max < t_min. Cheap (no
/// division), for code that only needs to reject such rays.
inline bool is_valid_ray(const Ray& ray) {
  constexpr float kMinNormal = std::numeric_limits<float>::min();
  const Vec3& d = ray.direction;
  return is_finite(ray.origin) && is_finite(d) &&
         (std::fabs(d.x) >= kMinNormal || std::fabs(d.y) >= kMinNormal || std::fabs(d.z) >= kMinNormal) &&
         !std::isnan(ray.t_min) && !std::isnan(ray.t_max) && ray.t_min <= ray.t_max;
}

/// Per-ray constants shared by every kernel. A ray with a NaN or infinite origin or direction component, a zero
/// direction, a NaN t bound, or t_max < t_min is "void": its interval is empty (t_min = +inf, t_max = -inf) and
/// every test rejects it, so bad rays never produce a hit. `direction` is the ray's as kernels read it
/// (readable_direction(): subnormal components are zero).
struct PreparedRay {
  Vec3 origin;
  Vec3 direction;
  Vec3 inv_direction;  ///< 1/d per axis; +-inf for +-0 components (the sign of zero is kept)
  int negative[3];     ///< 1 when the direction's sign bit is set (also for -0)
  float t_min;
  float t_max;  ///< inclusive
  // Watertight triangle test: kz is the dominant axis, (kx, ky) the other two in winding-preserving order.
  int kx, ky, kz;
  float shear_x, shear_y, shear_z;

  bool is_void() const { return !(t_min <= t_max); }

  explicit PreparedRay(const Ray& ray) : origin(ray.origin), direction(readable_direction(ray.direction)) {
    const Vec3& d = direction;
    if (is_valid_ray(ray)) {
      t_min = ray.t_min;
      t_max = ray.t_max;
    } else {
      t_min = std::numeric_limits<float>::infinity();
      t_max = -std::numeric_limits<float>::infinity();
    }
    for (int a = 0; a < 3; ++a) {
      inv_direction[a] = 1.0f / d[a];
      negative[a] = std::signbit(d[a]) ? 1 : 0;
    }
    const Vec3 ad = abs(d);
    kz = max_axis(ad);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (d[kz] < 0.0f) { const int tmp = kx; kx = ky; ky = tmp; }
    const float dz = d[kz] != 0.0f ? d[kz] : 1.0f;  // only a void ray has d[kz] == 0
    shear_x = d[kx] / dz;
    shear_y = d[ky] / dz;
    shear_z = 1.0f / dz;
  }
};

}  // namespace rayaccel
