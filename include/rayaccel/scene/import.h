// Scene loading: mesh files (PLY by our own reader; OBJ, glTF, STL, ... through assimp) and built-in scenes by
// name. Primitive id = triangle index in file order, polygons fan-triangulated (other tools' .rays/.hits rely on it).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "rayaccel/core/primitives.h"
#include "rayaccel/scene/geometry_table.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {

/// Reads a mesh file. Throws Error naming the file and the fault: unreadable, not a mesh, no triangles, index out
/// of range, or a build without mesh import (RAYACCEL_WITH_ASSIMP=OFF, RAYACCEL_HAVE_MESH_IMPORT == 0; PLY is still
/// read then). NaN/Inf vertices are kept (the Scene marks their triangles invalid, see scene.h); points and lines
/// are skipped.
/// - PLY files (recognised by their first line "ply") are read by read_ply() (ply_reader.h), which checks every
///   count and value; faces keep their file order and polygons are fan-triangulated (0, i, i+1).
/// - Other formats go through assimp with no post-processing step at all, so faces keep their file order; polygons
///   are then fan-triangulated (0, i, i+1) here. A file with several meshes is concatenated in scene-graph order:
///   the node tree depth-first, parents before children, each node's meshes in its own order, with the accumulated
///   node transforms applied (a mesh instanced by two nodes appears twice).
/// With `geometries`, it is reset to one geometry per mesh placed, in that order (meshes without triangles left out, as
/// import_mesh_hierarchy()'s placements; a PLY file is one geometry): the geometry ids of a plain multi-mesh scene.
TriangleMesh import_mesh(const std::filesystem::path& path, GeometryTable* geometries = nullptr);

/// A mesh file with its node hierarchy kept: each mesh once, and where the nodes place it.
struct MeshHierarchy {
  struct Placement {
    std::uint32_t mesh = 0;  ///< index into meshes
    /// The node's accumulated transform (mesh to file space), row-major 3x4.
    std::array<double, 12> transform{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  };
  /// The file's meshes in file order, each fan-triangulated as by import_mesh() (ids in file order), untransformed;
  /// meshes without triangles are left out (and the placements renumbered).
  std::vector<TriangleMesh> meshes;
  /// One per reference of a node to a mesh, in the scene-graph order of import_mesh(): import_mesh() is these meshes
  /// mapped by these transforms and concatenated (it maps in float, through assimp's matrices; a flattening in double
  /// may differ from it in the last bit where a transform does not map a vertex exactly).
  std::vector<Placement> placements;
};

/// import_mesh() without flattening the node hierarchy: a mesh used by several nodes is read once and placed
/// several times (the input of an instanced scene, instance/import_instanced.h). A PLY file is one mesh placed
/// once. Throws Error as import_mesh() does, and for a file with no placed triangles.
MeshHierarchy import_mesh_hierarchy(const std::filesystem::path& path);

/// A scene from a spec: "builtin:NAME[:key=value,...]" (see builtin_scenes.h) or a mesh file path. The scene is
/// named after the file stem or the builtin name. With `geometries`, it is reset to the scene's meshes as
/// import_mesh() numbers them (a builtin scene: one geometry).
Scene load_scene(std::string_view spec, GeometryTable* geometries = nullptr);

}  // namespace rayaccel
