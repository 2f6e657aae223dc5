// Scene loading: mesh files (PLY by our own reader; OBJ, glTF, STL, ... through assimp) and built-in procedural
// scenes by name.
// Primitive id = triangle index in file order; polygons are fan-triangulated in order (the .rays/.hits files of
// other tools rely on this).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "rayaccel/core/primitives.h"
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
TriangleMesh import_mesh(const std::filesystem::path& path);

/// A scene from a spec: "builtin:NAME[:key=value,...]" (see builtin_scenes.h) or a mesh file path. The scene is
/// named after the file stem or the builtin name.
Scene load_scene(std::string_view spec);

}  // namespace rayaccel
