// Light sampling for the recursive renderer.
#include "rayaccel/render/lights.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "rayaccel/core/error.h"
#include "rayaccel/render/sampling.h"

namespace rayaccel {

Vec3 light_sample(const Light& light, std::uint64_t stream, int k) {
  if (light.radius <= 0.0f) return light.position;
  const float z = 1.0f - 2.0f * uniform_float(stream, static_cast<std::uint64_t>(k), 0);
  const float phi = 2.0f * std::numbers::pi_v<float> * uniform_float(stream, static_cast<std::uint64_t>(k), 1);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return light.position + Vec3{r * std::cos(phi), r * std::sin(phi), z} * light.radius;
}

std::vector<Light> default_lights(const AABB& box, const Camera& camera, int samples, float radius_fraction) {
  if (samples < 1) throw Error("lights: " + std::to_string(samples) + " samples per light; at least 1");
  if (!(radius_fraction >= 0.0f && std::isfinite(radius_fraction))) {
    throw Error("lights: radius fraction " + std::to_string(radius_fraction) + " is not a finite value >= 0");
  }
  const CameraFrame frame = camera.frame(1, 1);
  const float distance = std::max(length(camera.at - camera.eye), 1e-6f);
  Light light;
  light.position = camera.eye + (frame.up + frame.right) * (0.25f * distance);
  if (!box.is_empty() && box.contains(camera.eye)) {
    // A camera inside the scene (a room): keep the light inside the box too, a twentieth of each extent from its
    // walls, rather than behind the ceiling.
    const Vec3 margin = box.extent() * 0.05f;
    for (int axis = 0; axis < 3; ++axis) {
      light.position[axis] = std::clamp(light.position[axis], box.lo[axis] + margin[axis], box.hi[axis] - margin[axis]);
    }
  }
  light.radius = radius_fraction * (box.is_empty() ? distance : length(box.extent()));
  light.samples = samples;
  const float to_target = length(camera.at - light.position);
  light.intensity = Vec3{1.0f, 0.95f, 0.85f} * (to_target * to_target);
  return {light};
}

}  // namespace rayaccel
