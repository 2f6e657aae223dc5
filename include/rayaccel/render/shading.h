// Shading quantities of a hit: the unit geometric normal every renderer and workload shades with.
#pragma once

#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/core/vec3.h"
#include "rayaccel/render/image.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {

/// Unit geometric normal at a hit (triangles: (v1-v0)x(v2-v0); spheres: outward; user primitives: their normal
/// callback, or facing the ray without one); zero for a miss.
Vec3 geometric_normal(const Scene& scene, const Ray& ray, const Hit& hit);

/// The background of images: a dark blue-grey.
inline constexpr Rgb kBackground{28, 30, 38};
/// The normals image's colour of a unit normal: |n| per axis as (r, g, b).
Rgb normal_colour(const Vec3& n);

}  // namespace rayaccel
