// The small case the CLI tests share: a PLY of 300 random triangles (plus a duplicate and a degenerate one) and a
// ray file aimed at them, written to a fresh directory.
#pragma once

#include <filesystem>
#include <vector>

#include "rayaccel/core/ray.h"
#include "rayaccel/core/primitives.h"

namespace rayaccel::testing {

struct SmallCase {
  std::filesystem::path dir, ply, rays;
  TriangleMesh mesh;
};

/// Writes a binary little-endian PLY in the format of shared/scenes (float xyz, uchar-count int faces).
void write_ply(const std::filesystem::path& path, const TriangleMesh& mesh);
/// 300 random triangles in [-1, 1]^3, then a copy of triangle 5 (ties in t) and a zero-area triangle.
TriangleMesh small_mesh();
/// Rays aimed at triangle centroids (some with a shortened t_max or a raised t_min) and random rays.
std::vector<Ray> small_rays(const TriangleMesh& mesh);
/// The case in a fresh directory named after the running test: small.ply and small.rays.
SmallCase make_small_case();

}  // namespace rayaccel::testing
