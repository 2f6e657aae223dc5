// Shading quantities of a hit: the unit geometric normal every renderer and workload shades with.
#pragma once

#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/core/vec3.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {

/// Unit geometric normal at a hit (triangles: (v1-v0)x(v2-v0); spheres: outward; user primitives: their normal
/// callback, or facing the ray without one); zero for a miss.
Vec3 geometric_normal(const Scene& scene, const Ray& ray, const Hit& hit);

}  // namespace rayaccel
