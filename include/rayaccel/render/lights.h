// Lights of the recursive renderer: point lights and spherical area lights (sampled by points on the sphere), and
// the default light of a scene.
#pragma once

#include <cstdint>
#include <vector>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/vec3.h"
#include "rayaccel/render/camera.h"

namespace rayaccel {

/// A light at `position`, or a sphere of `radius` around it (radius > 0) sampled at `samples` points per shading
/// point. Irradiance from a point at distance r is intensity / r^2 (cosine-weighted at the surface).
struct Light {
  Vec3 position;
  Vec3 intensity{1.0f, 1.0f, 1.0f};
  float radius = 0.0f;  ///< 0: a point light
  int samples = 1;      ///< points per shading point on a spherical light (>= 1)
};

/// Point `k` of `samples` on a spherical light for the shading point with random stream `stream`: uniform on the
/// sphere (Archimedes: uniform z and angle); the light's position for a point light.
Vec3 light_sample(const Light& light, std::uint64_t stream, int k);

/// The default lighting for a camera: one spherical light above and to the right of the eye (a quarter of the
/// eye-to-target distance each way), of radius 2% of the scene box's diagonal by default, with `samples` samples, bright
/// enough to give a surface at the target an irradiance of about 1; when the eye is inside the box (a room), the
/// light is kept inside it, a twentieth of each extent from its walls. Lit from near the viewpoint, every visible
/// surface of an open or closed scene gets light, and shadows fall just beside the objects that cast them.
/// radius_fraction (>= 0, 0 for a point light) sets the radius as a fraction of the box's diagonal.
std::vector<Light> default_lights(const AABB& box, const Camera& camera, int samples, float radius_fraction = 0.02f);

}  // namespace rayaccel
