// GeometryTable (geometry ids of a scene merged from several meshes) and scene_from_meshes().
#include "rayaccel/scene/geometry_table.h"

#include <algorithm>

#include "rayaccel/core/error.h"

namespace rayaccel {

std::uint32_t GeometryTable::add(std::uint32_t primitive_count) {
  const std::uint64_t total = std::uint64_t{first_.back()} + primitive_count;
  if (total >= kInvalidPrimId) {
    throw Error("geometry " + std::to_string(geometry_count()) + ": " + std::to_string(total) +
                " primitives in all, 2^32 - 1 or more (the limit of a scene's primitive ids)");
  }
  first_.push_back(static_cast<std::uint32_t>(total));
  return geometry_count() - 1;
}

std::uint32_t GeometryTable::geometry_of(std::uint32_t prim_id) const {
  if (prim_id >= primitive_count()) return kInvalidPrimId;
  // The last geometry whose first primitive is <= prim_id; empty geometries (equal firsts) are skipped past.
  const auto it = std::upper_bound(first_.begin(), first_.end(), prim_id);
  return static_cast<std::uint32_t>(it - first_.begin()) - 1;
}

std::uint32_t GeometryTable::local_primitive(std::uint32_t prim_id) const {
  const std::uint32_t geom = geometry_of(prim_id);
  return geom == kInvalidPrimId ? kInvalidPrimId : prim_id - first_[geom];
}

void GeometryTable::geometry_ids(std::span<const Hit> hits, std::span<std::uint32_t> out) const {
  if (hits.size() != out.size()) {
    throw Error("geometry_ids: " + std::to_string(hits.size()) + " hits but room for " + std::to_string(out.size()));
  }
  for (std::size_t i = 0; i < hits.size(); ++i) out[i] = geometry_of(hits[i].prim_id);
}

Scene scene_from_meshes(std::span<const TriangleMesh> meshes, GeometryTable& table, std::string name) {
  GeometryTable built;
  TriangleMesh merged;
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    const TriangleMesh& mesh = meshes[k];
    if (mesh.triangles.size() >= kInvalidPrimId) throw Error("mesh " + std::to_string(k) + ": too many triangles");
    built.add(static_cast<std::uint32_t>(mesh.triangles.size()));
    if (merged.vertices.size() + mesh.vertices.size() >= kInvalidPrimId) {
      throw Error("mesh " + std::to_string(k) + ": 2^32 - 1 vertices or more in all");
    }
    const auto base = static_cast<std::uint32_t>(merged.vertices.size());
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      std::array<std::uint32_t, 3> tri = mesh.triangles[i];
      for (std::uint32_t& index : tri) {
        if (index >= mesh.vertices.size()) {
          throw Error("mesh " + std::to_string(k) + ": triangle " + std::to_string(i) + " uses vertex index " +
                      std::to_string(index) + ", but the mesh has " + std::to_string(mesh.vertices.size()) +
                      " vertices");
        }
        index += base;
      }
      merged.triangles.push_back(tri);
    }
    merged.vertices.insert(merged.vertices.end(), mesh.vertices.begin(), mesh.vertices.end());
  }
  Scene scene = Scene::from_mesh(std::move(merged), std::move(name));
  table = std::move(built);
  return scene;
}

}  // namespace rayaccel
