// Signed distance to a closed triangle mesh for batches of points: the closest-point distance, negative where the
// crossing-parity inside test says inside (exact off the surface, unlike pseudo-normals, Baerentzen & Aanaes 2005).
#pragma once

#include <span>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/query/inside.h"

namespace rayaccel {

/// For each point: its distance to the scene, negated when inside_by_parity() says inside (a point on the surface has
/// distance 0 either way). `closest`, when not empty, receives the closest points too. Meaningful for closed meshes
/// (query/closed_mesh.h); on an open one the sign is the parity vote's. Throws Error as closest_points() and
/// inside_by_parity() do.
void signed_distances(const Accelerator& accel, std::span<const Vec3> points, std::span<float> distance,
                      std::span<ClosestPoint> closest = {}, const ParityInsideConfig& config = {});

}  // namespace rayaccel
