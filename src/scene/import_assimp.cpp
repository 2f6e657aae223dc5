// Mesh import: PLY files through our own reader (ply_reader.h), every other format through assimp (its PLY loader
// removed; glTF node graphs checked first, gltf_depth.h) with no post-processing (ids stay in file order; polygons are
// fan-triangulated here). Built only with RAYACCEL_WITH_ASSIMP=ON; import_without_assimp.cpp takes its place otherwise.
#include "rayaccel/scene/import.h"

#include <assimp/BaseImporter.h>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <new>
#include <string>
#include <vector>

#include "rayaccel/core/error.h"
#include "rayaccel/core/quoted_path.h"
#include "rayaccel/scene/ply_reader.h"
#include "gltf_depth.h"

namespace rayaccel {

namespace {

/// Fails with a clear message when the file is missing, not a regular file, empty, or cannot be opened; returns
/// its first bytes (at most 16).
std::vector<std::byte> check_readable(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw Error("cannot read mesh file " + quoted(path) + ": no such file");
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw Error("cannot read mesh file " + quoted(path) + ": not a regular file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read mesh file " + quoted(path) + ": cannot open it (permissions?)");
  std::vector<std::byte> start(16);
  in.read(reinterpret_cast<char*>(start.data()), static_cast<std::streamsize>(start.size()));
  start.resize(static_cast<std::size_t>(in.gcount()));
  if (start.empty()) throw Error("mesh file " + quoted(path) + " is empty, not a mesh");
  return start;
}

Vec3 transform_point(const aiMatrix4x4& m, const aiVector3D& p) {
  const aiVector3D q = m * p;
  return {q.x, q.y, q.z};
}

/// Appends one assimp mesh, its vertices mapped by `transform`; faces of 1 or 2 indices (points, lines) are
/// skipped and polygons fan-triangulated as (0, i, i+1).
void append_assimp_mesh(TriangleMesh& out, const aiScene& scene, unsigned mesh_index, const aiMatrix4x4& transform,
                        const std::filesystem::path& path) {
  const aiMesh& mesh = *scene.mMeshes[mesh_index];
  const auto base = static_cast<std::uint32_t>(out.vertices.size());
  out.vertices.reserve(out.vertices.size() + mesh.mNumVertices);
  for (unsigned i = 0; i < mesh.mNumVertices; ++i) {
    out.vertices.push_back(transform_point(transform, mesh.mVertices[i]));
  }
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& face = mesh.mFaces[f];
    for (unsigned k = 0; k < face.mNumIndices; ++k) {
      if (face.mIndices[k] >= mesh.mNumVertices) {
        const std::string name = mesh.mName.length > 0 ? std::string(" '") + mesh.mName.C_Str() + "'" : "";
        throw Error("mesh file " + quoted(path) + ": face " + std::to_string(f) + " of mesh " +
                    std::to_string(mesh_index) + name + " uses vertex index " + std::to_string(face.mIndices[k]) +
                    ", out of range (the mesh has " + std::to_string(mesh.mNumVertices) + " vertices)");
      }
    }
    for (unsigned k = 1; k + 1 < face.mNumIndices; ++k) {
      out.triangles.push_back({base + face.mIndices[0], base + face.mIndices[k], base + face.mIndices[k + 1]});
    }
  }
}

/// append_assimp_mesh(), and with `geometries` one geometry for the triangles it appended (none for a mesh without).
void append_geometry(TriangleMesh& out, GeometryTable* geometries, const aiScene& scene, unsigned mesh_index,
                     const aiMatrix4x4& transform, const std::filesystem::path& path) {
  const std::size_t before = out.triangles.size();
  append_assimp_mesh(out, scene, mesh_index, transform, path);
  const std::size_t added = out.triangles.size() - before;
  if (geometries && added > 0) {
    if (added >= kInvalidPrimId) throw Error("mesh file " + quoted(path) + ": too many triangles");
    geometries->add(static_cast<std::uint32_t>(added));
  }
}

/// Depth-first, pre-order walk of the node graph; each node's meshes in the node's order, with the accumulated
/// node transform applied (a mesh used by several nodes is appended once per use).
void append_node(TriangleMesh& out, GeometryTable* geometries, const aiScene& scene, const aiNode& node,
                 const aiMatrix4x4& parent, const std::filesystem::path& path) {
  const aiMatrix4x4 transform = parent * node.mTransformation;
  for (unsigned i = 0; i < node.mNumMeshes; ++i) {
    if (node.mMeshes[i] < scene.mNumMeshes) append_geometry(out, geometries, scene, node.mMeshes[i], transform, path);
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    append_node(out, geometries, scene, *node.mChildren[c], transform, path);
  }
}

/// Reads a non-PLY file with assimp, without post-processing: steps such as Triangulate, SortByPType,
/// JoinIdenticalVertices or FindDegenerates would reorder, split, weld or drop faces and break "primitive id =
/// triangle index in file order".
const aiScene& read_with_assimp(Assimp::Importer& importer, const std::filesystem::path& path) {
  gltf::check_node_depth(path);
  // Whatever assimp takes for a PLY (it looks for "ply" in the first 200 bytes) must not reach its PLY loader, which
  // loops forever on a header cut short; our reader has seen every file that is one.
  if (Assimp::BaseImporter* ply = importer.GetImporter("ply")) {
    if (importer.UnregisterLoader(ply) == aiReturn_SUCCESS) delete ply;
  }
  const aiScene* scene = nullptr;
  try {
    scene = importer.ReadFile(path.string(), 0);
  } catch (const std::bad_alloc&) {
    throw Error("mesh file " + quoted(path) + ": out of memory while assimp read it (a count in the file is "
                "larger than the file can hold?)");
  }
  if (!scene) {
    throw Error("mesh file " + quoted(path) + " is not a mesh assimp can read: " + importer.GetErrorString());
  }
  return *scene;
}

/// append_node() without flattening: records each node's reference to a mesh with its accumulated transform.
void place_node(MeshHierarchy& out, const std::vector<std::int64_t>& kept, const aiScene& scene, const aiNode& node,
                const aiMatrix4x4& parent) {
  const aiMatrix4x4 transform = parent * node.mTransformation;
  for (unsigned i = 0; i < node.mNumMeshes; ++i) {
    if (node.mMeshes[i] >= scene.mNumMeshes || kept[node.mMeshes[i]] < 0) continue;
    MeshHierarchy::Placement placement;
    placement.mesh = static_cast<std::uint32_t>(kept[node.mMeshes[i]]);
    for (unsigned r = 0; r < 3; ++r) {
      for (unsigned c = 0; c < 4; ++c) placement.transform[r * 4 + c] = transform[r][c];
    }
    out.placements.push_back(placement);
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) place_node(out, kept, scene, *node.mChildren[c], transform);
}

}  // namespace

TriangleMesh import_mesh(const std::filesystem::path& path, GeometryTable* geometries) {
  if (geometries) *geometries = GeometryTable();
  // PLY (reads_as_ply) never reaches assimp: its PLY reader loops forever on a file that ends inside its header and
  // accepts files with fewer elements than they declare.
  if (reads_as_ply(path, check_readable(path))) {
    TriangleMesh mesh = read_ply(path);
    if (mesh.triangles.empty()) throw Error("mesh file " + quoted(path) + " has no triangles");
    if (geometries) geometries->add(static_cast<std::uint32_t>(mesh.triangles.size()));
    return mesh;
  }
  Assimp::Importer importer;
  const aiScene& scene = read_with_assimp(importer, path);
  TriangleMesh mesh;
  if (scene.mRootNode) {
    append_node(mesh, geometries, scene, *scene.mRootNode, aiMatrix4x4{}, path);
  } else {
    for (unsigned i = 0; i < scene.mNumMeshes; ++i) append_geometry(mesh, geometries, scene, i, aiMatrix4x4{}, path);
  }
  if (mesh.triangles.empty()) throw Error("mesh file " + quoted(path) + " has no triangles");
  return mesh;
}

MeshHierarchy import_mesh_hierarchy(const std::filesystem::path& path) {
  MeshHierarchy out;
  if (reads_as_ply(path, check_readable(path))) {
    out.meshes.push_back(import_mesh(path));
    out.placements.push_back({});
    return out;
  }
  Assimp::Importer importer;
  const aiScene& scene = read_with_assimp(importer, path);
  std::vector<std::int64_t> kept(scene.mNumMeshes, -1);  // file mesh -> index in out.meshes, -1 without triangles
  for (unsigned i = 0; i < scene.mNumMeshes; ++i) {
    TriangleMesh mesh;
    append_assimp_mesh(mesh, scene, i, aiMatrix4x4{}, path);
    if (mesh.triangles.empty()) continue;
    kept[i] = static_cast<std::int64_t>(out.meshes.size());
    out.meshes.push_back(std::move(mesh));
  }
  if (scene.mRootNode) {
    place_node(out, kept, scene, *scene.mRootNode, aiMatrix4x4{});
  } else {
    for (std::size_t i = 0; i < out.meshes.size(); ++i) {
      MeshHierarchy::Placement placement;
      placement.mesh = static_cast<std::uint32_t>(i);
      out.placements.push_back(placement);
    }
  }
  if (out.placements.empty()) throw Error("mesh file " + quoted(path) + " has no triangles");
  return out;
}

}  // namespace rayaccel
