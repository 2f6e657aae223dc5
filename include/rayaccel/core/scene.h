// Scene: the primitives every accelerator is built over, with per-primitive bounds and the one dispatch point from
// a primitive id to its ray test.
//
// Rules for bad geometry (documented once, here):
// - A triangle with a NaN or infinite vertex coordinate, or a sphere with a non-finite center or a radius that is
//   not finite and > 0, is *invalid*: it keeps its id, is excluded from bounds() and build_references(), and is
//   never hit.
// - A zero-area (degenerate) triangle — edge cross product exactly zero, computed exactly from the stored floats —
//   is treated the same way: it keeps its id, is excluded from bounds() and build_references(), and is never hit
//   (in floating point the sheared test could otherwise report a hit on a collinear triangle). degenerate_count()
//   reports how many there are; invalid_count() counts only the non-finite ones.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
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

enum class PrimitiveKind { triangles, spheres, user };
const char* to_string(PrimitiveKind kind);

class Scene {
 public:
  Scene() = default;
  static Scene from_mesh(TriangleMesh mesh, std::string name = "mesh");
  static Scene from_spheres(std::vector<Sphere> spheres, std::string name = "spheres");
  static Scene from_user(UserPrimitives prims, std::string name = "user");

  const std::string& name() const { return name_; }
  void set_name(std::string name) { name_ = std::move(name); }
  PrimitiveKind kind() const { return kind_; }
  std::uint32_t primitive_count() const { return static_cast<std::uint32_t>(prim_bounds_.size()); }
  std::uint32_t invalid_count() const { return invalid_count_; }
  /// Primitives that are neither invalid nor degenerate: those build_references() returns.
  std::uint32_t valid_count() const { return primitive_count() - invalid_count_ - degenerate_count_; }
  std::uint32_t degenerate_count() const { return degenerate_count_; }
  /// Bounds of the valid primitives (empty when there are none).
  const AABB& bounds() const { return bounds_; }

  bool is_valid(std::uint32_t id) const { return !prim_bounds_[id].is_empty(); }
  /// Bounds of one primitive; empty for an invalid or degenerate one.
  const AABB& primitive_bounds(std::uint32_t id) const { return prim_bounds_[id]; }
  Vec3 primitive_centroid(std::uint32_t id) const { return prim_bounds_[id].center(); }
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
        const auto& t = triangle_vertices_[id];
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

  /// Unit geometric normal at a hit (triangles: (v1-v0)x(v2-v0); spheres: outward), for shading.
  Vec3 normal(const Ray& ray, const Hit& hit) const;

  // Triangle access (kind() == triangles).
  const TriangleMesh& mesh() const { return mesh_; }
  /// The three vertices of triangle id as stored for tracing (all zero for an invalid or degenerate triangle).
  const std::array<Vec3, 3>& triangle(std::uint32_t id) const { return triangle_vertices_[id]; }
  /// Replaces the vertex positions (same count and topology) and updates every derived bound: the input of refit.
  void set_vertices(std::span<const Vec3> vertices);
  /// Appends triangles (indices into the new vertex list after `vertices` are appended); returns the first new id.
  std::uint32_t append_triangles(std::span<const Vec3> vertices, std::span<const std::array<std::uint32_t, 3>> tris);

  // Sphere and user access.
  const std::vector<Sphere>& spheres() const { return spheres_; }
  const UserPrimitives& user_primitives() const { return user_; }

  /// Bytes held by the scene's own arrays (not counted in any accelerator's memory).
  std::size_t memory_bytes() const;

 private:
  void derive_triangle(std::uint32_t id);
  void finish_bounds();

  std::string name_;
  PrimitiveKind kind_ = PrimitiveKind::triangles;
  TriangleMesh mesh_;
  std::vector<std::array<Vec3, 3>> triangle_vertices_;
  std::vector<Sphere> spheres_;
  UserPrimitives user_;
  std::vector<AABB> prim_bounds_;
  AABB bounds_;
  std::uint32_t invalid_count_ = 0;
  std::uint32_t degenerate_count_ = 0;
};

}  // namespace rayaccel
