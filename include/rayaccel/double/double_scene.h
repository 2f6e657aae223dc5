// DoubleScene: the triangle scene of the double-precision path (vertices in double), checked on construction, with
// each triangle's box rounded outward to float so that the float-box structures of bvh/ can be built over it and
// every box contains its double triangle exactly.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/dvec3.h"
#include "rayaccel/core/mesh_d.h"
#include "rayaccel/core/primitives.h"

namespace rayaccel {

class DoubleScene {
 public:
  DoubleScene() = default;
  /// Takes the mesh. Throws Error naming the vertex and the value for a coordinate outside the double domain (NaN,
  /// infinite, above 2^64 or nonzero below 2^-64 in magnitude: core/ray_d.h), and naming the triangle for an index
  /// >= the vertex count. Triangles of zero area are kept and never hit.
  explicit DoubleScene(TriangleMeshD mesh);

  const TriangleMeshD& mesh() const { return mesh_; }
  std::uint32_t triangle_count() const { return static_cast<std::uint32_t>(triangles_.size()); }
  const std::array<DVec3, 3>& triangle(std::uint32_t id) const { return triangles_[id]; }
  /// The smallest float box that contains triangle `id` (each bound rounded outward).
  const AABB& triangle_box(std::uint32_t id) const { return boxes_[id]; }
  /// Box of all triangle boxes (empty when there are none).
  const AABB& bounds() const { return bounds_; }
  std::size_t memory_bytes() const;

 private:
  TriangleMeshD mesh_;
  std::vector<std::array<DVec3, 3>> triangles_;
  std::vector<AABB> boxes_;
  AABB bounds_;
};

/// The float mesh in double, each vertex moved by `offset` (one rounding per coordinate): for placing a float model
/// far from the origin.
TriangleMeshD to_double_mesh(const TriangleMesh& mesh, const DVec3& offset = {});
/// The double mesh rounded to float, vertex by vertex: what the float path can hold of it.
TriangleMesh to_float_mesh(const TriangleMeshD& mesh);

}  // namespace rayaccel
