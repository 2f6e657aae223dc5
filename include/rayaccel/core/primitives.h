// The primitive kinds a Scene can hold: indexed triangle meshes, analytic spheres, and user primitives given as
// callbacks (bounds + intersect), so every structure works on any of them.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/hit.h"
#include "rayaccel/core/huge_page_allocator.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/core/vec3.h"

namespace rayaccel {

/// Indexed triangle list; primitive id = index into `triangles`.
struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

/// Width of the indices in MeshBuffers.
enum class IndexType { uint16, uint32 };

/// Triangle buffers owned by the caller, read in place by Scene::from_buffers() (which states the lifetime rule).
/// Vertex i is three float32 (x, y, z) at `vertices + i * vertex_stride` bytes; triangle t is three indices of
/// `index_type` at `indices + t * triangle_stride` bytes. Unaligned buffers are fine (they are read with memcpy).
struct MeshBuffers {
  const void* vertices = nullptr;
  std::size_t vertex_count = 0;
  std::size_t vertex_stride = 3 * sizeof(float);  ///< bytes from one vertex to the next, at least 12
  const void* indices = nullptr;
  std::size_t triangle_count = 0;
  IndexType index_type = IndexType::uint32;
  std::size_t triangle_stride = 0;  ///< bytes from one triangle's indices to the next; 0 means packed (3 indices)
};

struct Sphere {
  Vec3 center;
  float radius = 1.0f;
};

/// Primitives defined by the caller. `bounds` must enclose every point `intersect` can report. `intersect` has the
/// contract of intersect_triangle(): on a hit with ray.t_min < t < hit.t it sets hit.t, hit.prim_id, hit.u, hit.v
/// and returns true. `normal` (optional) gives the surface normal at a hit for shading.
struct UserPrimitives {
  std::uint32_t count = 0;
  std::function<AABB(std::uint32_t prim_id)> bounds;
  std::function<bool(std::uint32_t prim_id, const PreparedRay& ray, Hit& hit)> intersect;
  std::function<Vec3(std::uint32_t prim_id, const Vec3& point)> normal;
};

/// What a builder sees of a primitive: its bounds (the centroid is bounds.center()) and its id.
struct PrimRef {
  AABB bounds;
  std::uint32_t prim_id = 0;
  Vec3 centroid() const { return bounds.center(); }
};

/// The references a build works on. Scenes of millions of triangles make arrays of tens of MB, so they live on
/// transparent huge pages (HugePageAllocator): filling them then takes one page fault per 2 MiB instead of per 4 KiB
/// (measured: 4 KiB faults were a third of a dragon build's pre-splitting and did not get faster with threads).
using PrimRefs = HugePageVector<PrimRef>;

}  // namespace rayaccel
