// Shading quantities of a hit (see render/shading.h).
#include "rayaccel/render/shading.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace rayaccel {

Vec3 geometric_normal(const Scene& scene, const Ray& ray, const Hit& hit) {
  if (!hit.found()) return {};
  const Vec3 p = ray.origin + ray.direction * hit.t;
  switch (scene.kind()) {
    case PrimitiveKind::triangles: {
      const std::array<Vec3, 3> t = scene.triangle(hit.prim_id);
      return normalize(cross(t[1] - t[0], t[2] - t[0]));
    }
    case PrimitiveKind::spheres:
      return normalize(p - scene.spheres()[hit.prim_id].center);
    case PrimitiveKind::user: {
      const UserPrimitives& user = scene.user_primitives();
      return user.normal ? normalize(user.normal(hit.prim_id, p)) : normalize(-ray.direction);
    }
  }
  return {};
}

Rgb normal_colour(const Vec3& n) {
  const Vec3 a = abs(n);
  return {static_cast<std::uint8_t>(std::lround(std::clamp(a.x, 0.0f, 1.0f) * 255.0f)),
          static_cast<std::uint8_t>(std::lround(std::clamp(a.y, 0.0f, 1.0f) * 255.0f)),
          static_cast<std::uint8_t>(std::lround(std::clamp(a.z, 0.0f, 1.0f) * 255.0f))};
}

}  // namespace rayaccel
