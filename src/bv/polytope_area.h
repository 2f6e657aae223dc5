// Surface area of a box cut by half-spaces, for volumes bounded by arbitrary planes (the capped hull): every face
// polygon is its plane clipped by all other half-spaces (Sutherland & Hodgman 1974 on a convex polygon in 3D), in
// double precision.
#pragma once

#include <span>

#include "fit_support.h"
#include "rayaccel/core/aabb.h"

namespace rayaccel::bv_detail {

/// The half-space {p : dot(normal, p) <= offset}; the normal need not be unit.
struct Halfspace {
  Vec3d normal;
  double offset = 0.0;
};

/// Area of box ∩ every cut (double-sided for a flat polytope, like AABB::surface_area; 0 for an empty box). Points
/// within 2e-12 of the box's scale of a plane count as on it, so coincident planes do not clip each other away.
double polytope_area(const AABB& box, std::span<const Halfspace> cuts);

}  // namespace rayaccel::bv_detail
