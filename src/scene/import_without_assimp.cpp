// Mesh import in a build without assimp (RAYACCEL_WITH_ASSIMP=OFF): PLY files through our own reader
// (ply_reader.h); every other file is refused with the reason.
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/scene/import.h"
#include "rayaccel/scene/file_extension.h"
#include "rayaccel/scene/ply_reader.h"

namespace rayaccel {

namespace {

[[noreturn]] void refuse_without_assimp(const std::filesystem::path& path) {
  throw Error("cannot read mesh file '" + path.string() +
              "': this rayaccel was built without assimp (RAYACCEL_WITH_ASSIMP=OFF) and reads only PLY files; use a "
              "PLY file, a builtin: scene or a Scene built from your own arrays");
}

}  // namespace

MeshHierarchy import_mesh_hierarchy(const std::filesystem::path& path) {
  MeshHierarchy out;
  out.meshes.push_back(import_mesh(path));
  out.placements.push_back({});
  return out;
}

TriangleMesh import_mesh(const std::filesystem::path& path, GeometryTable* geometries) {
  if (lowercase_extension(path) == ".ply") {
    TriangleMesh mesh = read_ply(path);
    if (mesh.triangles.empty()) throw Error("mesh file '" + path.string() + "' has no triangles");
    if (geometries) {
      *geometries = GeometryTable();
      geometries->add(static_cast<std::uint32_t>(mesh.triangles.size()));
    }
    return mesh;
  }
  refuse_without_assimp(path);
  return {};
}

}  // namespace rayaccel
