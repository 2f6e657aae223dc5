// GeometryTable: which mesh (geometry id) each primitive of a scene merged from several meshes came from, as Embree's
// geomID/primID pair: mesh k owns the consecutive primitive ids [first_primitive(k), first_primitive(k + 1)).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/primitives.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {

class GeometryTable {
 public:
  /// Appends a geometry of `primitive_count` primitives after the others; returns its id (0, 1, ...). Throws Error
  /// when the primitives of all geometries would reach 2^32 - 1 (kInvalidPrimId, the miss marker).
  std::uint32_t add(std::uint32_t primitive_count);

  std::uint32_t geometry_count() const { return static_cast<std::uint32_t>(first_.size()) - 1; }
  /// Primitives of all geometries together.
  std::uint32_t primitive_count() const { return first_.back(); }
  /// The scene-wide id of geometry `geom_id`'s first primitive (primitive_count() for geom_id == geometry_count()).
  std::uint32_t first_primitive(std::uint32_t geom_id) const { return first_.at(geom_id); }
  std::uint32_t primitive_count(std::uint32_t geom_id) const { return first_.at(geom_id + 1) - first_.at(geom_id); }
  /// first_primitive(k) for k = 0 .. geometry_count(): what QueryContext::geometry_starts takes.
  std::span<const std::uint32_t> starts() const { return first_; }
  /// The geometry holding scene-wide primitive `prim_id`; kInvalidPrimId for an id out of range (a miss).
  std::uint32_t geometry_of(std::uint32_t prim_id) const;
  /// `prim_id`'s index within its geometry; kInvalidPrimId for an id out of range (a miss).
  std::uint32_t local_primitive(std::uint32_t prim_id) const;
  /// The parallel array of a batch of hits: out[i] = geometry_of(hits[i].prim_id). Throws Error unless the sizes match.
  void geometry_ids(std::span<const Hit> hits, std::span<std::uint32_t> out) const;

 private:
  std::vector<std::uint32_t> first_{0};  // first_[k]: first primitive of geometry k; back(): primitive_count()
};

/// One triangle scene of several meshes, mesh k's triangles first_primitive(k) onward in `table` (which is reset to
/// the meshes given), each mesh's vertex indices its own. Throws Error naming the mesh and triangle for an index out of
/// range, and as GeometryTable::add() for too many triangles.
Scene scene_from_meshes(std::span<const TriangleMesh> meshes, GeometryTable& table, std::string name = "meshes");

}  // namespace rayaccel
