// Scene: the primitives every accelerator is built over, with per-primitive bounds and the one dispatch point from
// a primitive id to its ray test; the rules for invalid and degenerate primitives are stated once, below.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/hit.h"
#include "rayaccel/core/primitives.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/geometry/ray_sphere.h"
#include "rayaccel/geometry/ray_triangle.h"

namespace rayaccel {

// Rules for bad geometry (documented once, here):
// - A triangle with a NaN or infinite vertex coordinate, or a sphere with a non-finite center or a radius that is
//   not finite and > 0, is *invalid*: it keeps its id, is excluded from bounds() and build_references(), and is
//   never hit.
// - A zero-area (degenerate) triangle — edge cross product exactly zero, computed exactly from the stored floats —
//   is treated the same way: it keeps its id, is excluded from bounds() and build_references(), and is never hit
//   (in floating point the sheared test could otherwise report a hit on a collinear triangle). degenerate_count()
//   reports how many there are; invalid_count() counts only the non-finite ones.

enum class PrimitiveKind { triangles, spheres, user };
const char* to_string(PrimitiveKind kind);

class Scene {
 public:
  Scene() = default;
  /// A triangle scene that owns a copy of `mesh` (moved in when given an rvalue).
  static Scene from_mesh(TriangleMesh mesh, std::string name = "mesh");
  /// A triangle scene over the caller's buffers, which it reads in place and never copies: the scene keeps only
  /// one validity byte a triangle. Lifetime rule: the buffers must stay alive, at the same addresses,
  /// for as long as the scene or any accelerator built over it is used, and must not change meanwhile; after
  /// writing new vertex positions in place, call buffers_changed() on the scene, then refit or rebuild the
  /// accelerators. Indices must not change at all (make a new scene). Throws Error for a null pointer with a
  /// non-zero count, a vertex stride under 12 bytes, a triangle stride under three indices, or an index >=
  /// vertex_count (naming the triangle).
  static Scene from_buffers(const MeshBuffers& buffers, std::string name = "buffers");
  static Scene from_spheres(std::vector<Sphere> spheres, std::string name = "spheres");
  static Scene from_user(UserPrimitives prims, std::string name = "user");

  const std::string& name() const { return name_; }
  void set_name(std::string name) { name_ = std::move(name); }
  PrimitiveKind kind() const { return kind_; }
  std::uint32_t primitive_count() const { return static_cast<std::uint32_t>(valid_.size()); }
  std::uint32_t invalid_count() const { return invalid_count_; }
  /// Primitives that are neither invalid nor degenerate: those build_references() returns.
  std::uint32_t valid_count() const { return primitive_count() - invalid_count_ - degenerate_count_; }
  std::uint32_t degenerate_count() const { return degenerate_count_; }
  /// Bounds of the valid primitives (empty when there are none).
  const AABB& bounds() const { return bounds_; }

  bool is_valid(std::uint32_t id) const { return valid_[id] != 0; }
  /// Bounds of one primitive; empty for an invalid or degenerate one. A triangle's are computed from its vertices
  /// (the scene stores no per-triangle boxes).
  AABB primitive_bounds(std::uint32_t id) const {
    if (kind_ != PrimitiveKind::triangles) return prim_bounds_[id];
    if (!is_valid(id)) return AABB::empty();
    const auto [a, b, c] = source_triangle(id);
    return AABB::of_point(a).extend(b).extend(c);
  }
  Vec3 primitive_centroid(std::uint32_t id) const { return primitive_bounds(id).center(); }
  /// One reference per valid primitive, in id order: the input of every builder.
  /// One reference per valid primitive, in id order. `extra_capacity` more references fit without reallocation (for
  /// a caller that appends, as pre-splitting does).
  PrimRefs build_references(std::size_t extra_capacity = 0) const;

  /// Points whose convex hull encloses the primitive, for fitting bounding volumes: a triangle's 3 vertices, else
  /// the 8 corners of its box. Returns how many were written to `out`.
  int hull_points(std::uint32_t id, std::array<Vec3, 8>& out) const;

  /// Ray test of one primitive (see intersect_triangle() for the contract).
  bool intersect(std::uint32_t id, const PreparedRay& ray, Hit& hit) const {
    switch (kind_) {
      case PrimitiveKind::triangles: {
        if (!is_valid(id)) return false;
        const std::array<Vec3, 3> t = source_triangle(id);
        return intersect_triangle(ray, t[0], t[1], t[2], id, hit);
      }
      case PrimitiveKind::spheres: {
        const Sphere& s = spheres_[id];
        return intersect_sphere(ray, s.center, s.radius, id, hit);
      }
      case PrimitiveKind::user:
        return user_.intersect(id, ray, hit);
    }
    return false;
  }

  // Triangle access (kind() == triangles).
  /// The owned mesh; empty for a scene over caller buffers (borrows_buffers()).
  const TriangleMesh& mesh() const { return mesh_; }
  /// True for a scene made by from_buffers(), which reads the caller's arrays.
  bool borrows_buffers() const { return borrowed_; }
  /// Vertices of the mesh, owned or borrowed.
  std::size_t vertex_count() const { return borrowed_ ? buffers_.vertex_count : mesh_.vertices.size(); }
  /// The three vertices of triangle id as traced (all zero for an invalid or degenerate triangle).
  std::array<Vec3, 3> triangle(std::uint32_t id) const {
    return is_valid(id) ? source_triangle(id) : std::array<Vec3, 3>{};
  }
  /// Replaces the vertex positions (same count and topology) and updates every derived bound: the input of refit.
  /// Throws Error for a scene over caller buffers (write them, then call buffers_changed()).
  void set_vertices(std::span<const Vec3> vertices);
  /// Re-reads the caller's buffers after their vertex positions changed in place, and updates every derived bound:
  /// the input of refit. Throws Error for a scene that owns its mesh.
  void buffers_changed();
  /// Appends triangles (indices into the new vertex list after `vertices` are appended); returns the first new id.
  /// Throws Error for a scene over caller buffers.
  std::uint32_t append_triangles(std::span<const Vec3> vertices, std::span<const std::array<std::uint32_t, 3>> tris);

  // Sphere and user access.
  const std::vector<Sphere>& spheres() const { return spheres_; }
  const UserPrimitives& user_primitives() const { return user_; }

  /// Bytes held by the scene's own arrays (not counted in any accelerator's memory; caller buffers not counted).
  std::size_t memory_bytes() const;

 private:
  /// Triangle id read from the caller's buffers (indices were checked when the scene was made).
  std::array<Vec3, 3> buffer_triangle(std::uint32_t id) const {
    const auto* indices = static_cast<const unsigned char*>(buffers_.indices) + id * buffers_.triangle_stride;
    const auto* vertices = static_cast<const unsigned char*>(buffers_.vertices);
    std::array<Vec3, 3> out;
    for (int k = 0; k < 3; ++k) {
      std::uint32_t index;
      if (buffers_.index_type == IndexType::uint16) {
        std::uint16_t narrow;
        std::memcpy(&narrow, indices + k * sizeof(narrow), sizeof(narrow));
        index = narrow;
      } else {
        std::memcpy(&index, indices + k * sizeof(index), sizeof(index));
      }
      float xyz[3];
      std::memcpy(xyz, vertices + index * buffers_.vertex_stride, sizeof(xyz));
      out[k] = Vec3{xyz[0], xyz[1], xyz[2]};
    }
    return out;
  }
  /// The three vertices of triangle id as given (owned mesh or caller buffers), before validation.
  std::array<Vec3, 3> source_triangle(std::uint32_t id) const {
    if (borrowed_) return buffer_triangle(id);
    const auto& idx = mesh_.triangles[id];
    return {mesh_.vertices[idx[0]], mesh_.vertices[idx[1]], mesh_.vertices[idx[2]]};
  }
  void derive_triangle(std::uint32_t id);
  void finish_bounds();

  std::string name_;
  PrimitiveKind kind_ = PrimitiveKind::triangles;
  TriangleMesh mesh_;
  MeshBuffers buffers_;  // with borrowed_: the caller's arrays, triangle_stride resolved (never 0)
  bool borrowed_ = false;
  std::vector<Sphere> spheres_;
  UserPrimitives user_;
  std::vector<std::uint8_t> valid_;  // one byte per primitive: 1 when neither invalid nor degenerate
  std::vector<AABB> prim_bounds_;    // spheres and user primitives only (a triangle's box comes from its vertices)
  AABB bounds_;
  std::uint32_t invalid_count_ = 0;
  std::uint32_t degenerate_count_ = 0;
};

}  // namespace rayaccel
