// Inside tests for batches of points: crossing parity over several rays (Jordan-Brouwer), and the generalised
// winding number (Jacobson, Kavan, Sorkine-Hornung 2013; solid angles after Van Oosterom & Strackee 1983).
#pragma once

#include <cstdint>
#include <span>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/core/vec3.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {

struct ParityInsideConfig {
  /// Rays per point, 1..7, odd so the vote cannot tie. Their directions are fixed and none is parallel to an axis or
  /// to a diagonal, so axis-aligned and diagonal faces are not met edge-on.
  int ray_count = 3;
};

/// For each point: 1 when the majority of ray_count rays from it (t in (0, inf)) cross the surface an odd number of
/// times, else 0. Exact for a closed mesh and a point off its surface by more than the kernel's t error (see
/// README, "Exactness"); a point on the surface may get either answer. `accel` must support queries
/// (Accelerator::supports_queries); throws Error for a bad config, sizes that differ, or a non-finite point (naming
/// its index).
void inside_by_parity(const Accelerator& accel, std::span<const Vec3> points, std::span<std::uint8_t> inside,
                      const ParityInsideConfig& config = {});

/// The generalised winding number of each point with respect to the scene's valid triangles (orientation as stored:
/// counter-clockwise seen from outside gives 1 inside), summed in double over every triangle, in parallel over the
/// points. A point on a triangle gets that triangle's contribution 0. Throws Error for a non-triangle scene, sizes
/// that differ, or a non-finite point.
void winding_numbers(const Scene& scene, std::span<const Vec3> points, std::span<double> winding);

}  // namespace rayaccel
