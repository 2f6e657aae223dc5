// Scene construction: validates primitives, marks the valid ones and counts invalid and degenerate ones; triangles
// come from an owned mesh or from the caller's buffers and are stored once (no per-triangle copies or boxes).
#include "rayaccel/scene/scene.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/geometry/exact_edge.h"

namespace rayaccel {

const char* to_string(PrimitiveKind kind) {
  switch (kind) {
    case PrimitiveKind::triangles: return "triangles";
    case PrimitiveKind::spheres: return "spheres";
    case PrimitiveKind::user: return "user";
  }
  return "?";
}

namespace {

/// Zero area in exact arithmetic: each component of the cross product (b - a) x (c - a) is the edge function of b
/// and c for a ray from a along that axis, whose exact sign exact_edge_function() gives. (Computed in double, the
/// differences of floats far apart in magnitude round, and a thin triangle 1e24 long read as zero area: fuzz corpus
/// thin-triangle-read-as-zero-area.)
bool has_zero_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  for (int k = 0; k < 3; ++k) {
    Vec3 axis{0.0f, 0.0f, 0.0f};
    axis[static_cast<std::size_t>(k)] = 1.0f;
    if (exact_edge_function(a, axis, (k + 1) % 3, (k + 2) % 3, k, b, c).sign != 0) return false;
  }
  return true;
}

/// Calls derive(id) for every id in [first, last) on the threads TBB has (the scene's preparation, which Embree's
/// build does in parallel too): each call writes only its own primitive's entries.
template <class Derive>
void derive_all(std::size_t first, std::size_t last, Derive&& derive) {
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(static_cast<std::uint32_t>(first),
                                                      static_cast<std::uint32_t>(last), 4096),
                    [&](const tbb::blocked_range<std::uint32_t>& range) {
                      for (std::uint32_t id = range.begin(); id != range.end(); ++id) derive(id);
                    });
}

}  // namespace

Scene Scene::from_mesh(TriangleMesh mesh, std::string name) {
  Scene s;
  s.name_ = std::move(name);
  s.kind_ = PrimitiveKind::triangles;
  const auto vertex_count = mesh.vertices.size();
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    for (std::uint32_t index : mesh.triangles[i]) {
      if (index >= vertex_count) {
        throw Error("triangle " + std::to_string(i) + " uses vertex index " + std::to_string(index) +
                    ", but the mesh has only " + std::to_string(vertex_count) + " vertices");
      }
    }
  }
  s.mesh_ = std::move(mesh);
  s.valid_.resize(s.mesh_.triangles.size());
  derive_all(0, s.mesh_.triangles.size(), [&](std::uint32_t i) { s.derive_triangle(i); });
  s.finish_bounds();
  return s;
}

Scene Scene::from_buffers(const MeshBuffers& buffers, std::string name) {
  const std::size_t index_size = buffers.index_type == IndexType::uint16 ? 2 : 4;
  if (buffers.vertex_count > 0 && buffers.vertices == nullptr) throw Error("from_buffers: vertices is null");
  if (buffers.triangle_count > 0 && buffers.indices == nullptr) throw Error("from_buffers: indices is null");
  if (buffers.vertex_stride < 3 * sizeof(float)) {
    throw Error("from_buffers: vertex_stride " + std::to_string(buffers.vertex_stride) +
                " is under the 12 bytes of three float32");
  }
  if (buffers.triangle_stride != 0 && buffers.triangle_stride < 3 * index_size) {
    throw Error("from_buffers: triangle_stride " + std::to_string(buffers.triangle_stride) + " is under the " +
                std::to_string(3 * index_size) + " bytes of three indices");
  }
  if (buffers.triangle_count >= std::uint32_t(-1)) throw Error("from_buffers: 2^32 - 1 triangles or more");
  Scene s;
  s.name_ = std::move(name);
  s.kind_ = PrimitiveKind::triangles;
  s.borrowed_ = true;
  s.buffers_ = buffers;
  if (s.buffers_.triangle_stride == 0) s.buffers_.triangle_stride = 3 * index_size;
  const auto* indices = static_cast<const unsigned char*>(buffers.indices);
  for (std::size_t i = 0; i < buffers.triangle_count; ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      std::uint32_t index = 0;
      const unsigned char* at = indices + i * s.buffers_.triangle_stride + k * index_size;
      if (index_size == 2) {
        std::uint16_t narrow;
        std::memcpy(&narrow, at, sizeof(narrow));
        index = narrow;
      } else {
        std::memcpy(&index, at, sizeof(index));
      }
      if (index >= buffers.vertex_count) {
        throw Error("from_buffers: triangle " + std::to_string(i) + " uses vertex index " + std::to_string(index) +
                    ", but there are only " + std::to_string(buffers.vertex_count) + " vertices");
      }
    }
  }
  s.valid_.resize(buffers.triangle_count);
  derive_all(0, buffers.triangle_count, [&](std::uint32_t i) { s.derive_triangle(i); });
  s.finish_bounds();
  return s;
}

Scene Scene::from_spheres(std::vector<Sphere> spheres, std::string name) {
  Scene s;
  s.name_ = std::move(name);
  s.kind_ = PrimitiveKind::spheres;
  s.spheres_ = std::move(spheres);
  s.prim_bounds_.resize(s.spheres_.size());
  s.valid_.resize(s.spheres_.size());
  for (std::size_t i = 0; i < s.spheres_.size(); ++i) {
    const Sphere& sp = s.spheres_[i];
    if (is_finite(sp.center) && std::isfinite(sp.radius) && sp.radius > 0.0f) {
      const Vec3 r{sp.radius};
      // Widen by one relative ulp-ish margin so float rounding of center +- radius never cuts the surface.
      const Vec3 pad = abs(sp.center) * 0x1p-22f + Vec3{sp.radius * 0x1p-22f};
      s.prim_bounds_[i] = AABB(sp.center - r - pad, sp.center + r + pad);
      s.valid_[i] = 1;
    }
  }
  s.finish_bounds();
  return s;
}

Scene Scene::from_user(UserPrimitives prims, std::string name) {
  if (prims.count > 0 && (!prims.bounds || !prims.intersect)) {
    throw Error("user primitives need both a bounds and an intersect callback");
  }
  Scene s;
  s.name_ = std::move(name);
  s.kind_ = PrimitiveKind::user;
  s.user_ = std::move(prims);
  s.prim_bounds_.resize(s.user_.count);
  s.valid_.resize(s.user_.count);
  for (std::uint32_t i = 0; i < s.user_.count; ++i) {
    const AABB b = s.user_.bounds(i);
    if (b.is_finite() && !b.is_empty()) {
      s.prim_bounds_[i] = b;
      s.valid_[i] = 1;
    }
  }
  s.finish_bounds();
  return s;
}

void Scene::derive_triangle(std::uint32_t id) {
  const auto [a, b, c] = source_triangle(id);
  valid_[id] = is_finite(a) && is_finite(b) && is_finite(c) && !has_zero_area(a, b, c) ? 1 : 0;
}

void Scene::finish_bounds() {
  struct Totals {
    AABB bounds;
    std::uint32_t invalid = 0, degenerate = 0;
  };
  // Min, max and counts: the same totals in any order, so with any number of threads.
  const Totals totals = tbb::parallel_reduce(
      tbb::blocked_range<std::uint32_t>(0, primitive_count(), 8192), Totals{},
      [&](const tbb::blocked_range<std::uint32_t>& range, Totals t) {
        for (std::uint32_t i = range.begin(); i != range.end(); ++i) {
          if (is_valid(i)) {
            t.bounds.extend(primitive_bounds(i));
            continue;
          }
          // Excluded: a degenerate triangle has finite vertices in the mesh; an invalid primitive does not.
          bool degenerate = false;
          if (kind_ == PrimitiveKind::triangles) {
            const auto [a, b, c] = source_triangle(i);
            degenerate = is_finite(a) && is_finite(b) && is_finite(c);
          }
          ++(degenerate ? t.degenerate : t.invalid);
        }
        return t;
      },
      [](Totals a, const Totals& b) {
        a.bounds.extend(b.bounds);
        a.invalid += b.invalid;
        a.degenerate += b.degenerate;
        return a;
      });
  bounds_ = totals.bounds;
  invalid_count_ = totals.invalid;
  degenerate_count_ = totals.degenerate;
}

PrimRefs Scene::build_references(std::size_t extra_capacity) const {
  // In parallel, in id order: each block of ids counts its valid primitives, a prefix sum gives where its
  // references start, and each block then writes its own (the same array on any number of threads).
  constexpr std::uint32_t kBlock = 16384;
  const std::uint32_t count = primitive_count();
  const std::uint32_t blocks = (count + kBlock - 1) / kBlock;
  std::vector<std::uint32_t> starts(blocks + 1, 0);
  tbb::parallel_for(std::uint32_t{0}, blocks, [&](std::uint32_t block) {
    const std::uint32_t end = std::min(count, (block + 1) * kBlock);
    std::uint32_t valid = 0;
    for (std::uint32_t i = block * kBlock; i < end; ++i) valid += valid_[i];
    starts[block + 1] = valid;
  });
  for (std::uint32_t block = 0; block < blocks; ++block) starts[block + 1] += starts[block];
  PrimRefs refs;
  refs.reserve(valid_count() + extra_capacity);
  refs.resize(valid_count());
  tbb::parallel_for(std::uint32_t{0}, blocks, [&](std::uint32_t block) {
    const std::uint32_t end = std::min(count, (block + 1) * kBlock);
    std::uint32_t out = starts[block];
    for (std::uint32_t i = block * kBlock; i < end; ++i) {
      if (is_valid(i)) refs[out++] = {primitive_bounds(i), i};
    }
  });
  return refs;
}

int Scene::hull_points(std::uint32_t id, std::array<Vec3, 8>& out) const {
  if (kind_ == PrimitiveKind::triangles) {
    const std::array<Vec3, 3> t = triangle(id);
    out[0] = t[0];
    out[1] = t[1];
    out[2] = t[2];
    return 3;
  }
  const AABB b = primitive_bounds(id);
  for (int corner = 0; corner < 8; ++corner) {
    out[corner] = {(corner & 1) ? b.hi.x : b.lo.x, (corner & 2) ? b.hi.y : b.lo.y, (corner & 4) ? b.hi.z : b.lo.z};
  }
  return 8;
}

void Scene::set_vertices(std::span<const Vec3> vertices) {
  if (kind_ != PrimitiveKind::triangles) throw Error("set_vertices: the scene does not hold a triangle mesh");
  if (borrowed_) throw Error("set_vertices: the scene reads the caller's buffers; write them, then buffers_changed()");
  if (vertices.size() != mesh_.vertices.size()) {
    throw Error("set_vertices: got " + std::to_string(vertices.size()) + " vertices, the mesh has " +
                std::to_string(mesh_.vertices.size()));
  }
  mesh_.vertices.assign(vertices.begin(), vertices.end());
  derive_all(0, mesh_.triangles.size(), [&](std::uint32_t i) { derive_triangle(i); });
  finish_bounds();
}

void Scene::buffers_changed() {
  if (!borrowed_) throw Error("buffers_changed: the scene owns its mesh; use set_vertices()");
  derive_all(0, valid_.size(), [&](std::uint32_t i) { derive_triangle(i); });
  finish_bounds();
}

std::uint32_t Scene::append_triangles(std::span<const Vec3> vertices,
                                      std::span<const std::array<std::uint32_t, 3>> tris) {
  if (kind_ != PrimitiveKind::triangles) throw Error("append_triangles: the scene does not hold a triangle mesh");
  if (borrowed_) throw Error("append_triangles: the scene reads the caller's buffers, which it cannot grow");
  const auto first_id = static_cast<std::uint32_t>(mesh_.triangles.size());
  const std::size_t new_vertex_count = mesh_.vertices.size() + vertices.size();
  for (std::size_t i = 0; i < tris.size(); ++i) {
    for (std::uint32_t index : tris[i]) {
      if (index >= new_vertex_count) {
        throw Error("append_triangles: new triangle " + std::to_string(i) + " uses vertex index " +
                    std::to_string(index) + ", but the mesh will have only " + std::to_string(new_vertex_count));
      }
    }
  }
  mesh_.vertices.insert(mesh_.vertices.end(), vertices.begin(), vertices.end());
  mesh_.triangles.insert(mesh_.triangles.end(), tris.begin(), tris.end());
  valid_.resize(mesh_.triangles.size());
  derive_all(first_id, mesh_.triangles.size(), [&](std::uint32_t i) { derive_triangle(i); });
  finish_bounds();
  return first_id;
}

std::size_t Scene::memory_bytes() const {
  return mesh_.vertices.size() * sizeof(Vec3) + mesh_.triangles.size() * sizeof(mesh_.triangles[0]) +
         spheres_.size() * sizeof(Sphere) + prim_bounds_.size() * sizeof(AABB) + valid_.size() * sizeof(valid_[0]);
}

}  // namespace rayaccel
