// The small case the CLI tests share: a PLY of 300 random triangles (plus a duplicate and a degenerate one) and a
// ray file aimed at them, written to a fresh directory.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <vector>

#include "rayaccel/core/ray.h"
#include "rayaccel/core/primitives.h"

namespace rayaccel::testing {

struct SmallCase {
  std::filesystem::path dir, ply, rays;
  TriangleMesh mesh;
};

/// Writes a binary little-endian PLY of `mesh` (int faces with a uchar count, as shared/scenes) with vertex
/// coordinates of the given PLY type ("float" or "double").
template <class Mesh>
void write_ply(const std::filesystem::path& path, const Mesh& mesh, const char* type = "float") {
  std::ofstream out(path, std::ios::binary);
  out << "ply\nformat binary_little_endian 1.0\nelement vertex " << mesh.vertices.size() << "\nproperty " << type
      << " x\nproperty " << type << " y\nproperty " << type << " z\nelement face " << mesh.triangles.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& v : mesh.vertices) out.write(reinterpret_cast<const char*>(&v), sizeof(v));
  for (const auto& t : mesh.triangles) {
    const unsigned char three = 3;
    out.write(reinterpret_cast<const char*>(&three), 1);
    for (std::uint32_t i : t) {
      const std::int32_t index = static_cast<std::int32_t>(i);
      out.write(reinterpret_cast<const char*>(&index), sizeof(index));
    }
  }
}

/// 300 random triangles in [-1, 1]^3, then a copy of triangle 5 (ties in t) and a zero-area triangle.
TriangleMesh small_mesh();
/// Rays aimed at triangle centroids (some with a shortened t_max or a raised t_min) and random rays.
std::vector<Ray> small_rays(const TriangleMesh& mesh);
/// The case in a fresh directory named after the running test: small.ply and small.rays.
SmallCase make_small_case();

}  // namespace rayaccel::testing
