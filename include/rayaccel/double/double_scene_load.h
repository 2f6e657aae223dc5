// Loading a scene for the double-precision path: a PLY file's coordinates as read (so `property double` keeps its 53
// bits); other mesh files and builtins through the float loader (scene/import.h), exact in double.
#pragma once

#include <string>
#include <string_view>

#include "rayaccel/core/dvec3.h"
#include "rayaccel/core/mesh_d.h"

namespace rayaccel {

struct NamedMeshD {
  TriangleMeshD mesh;
  std::string name;  ///< the file's stem, or the builtin's name
};

/// The triangle mesh of a scene spec (a mesh file path or "builtin:NAME[:key=value,...]", as load_scene() takes) in
/// double, every vertex moved by `offset` (rounded once, in double). Throws Error naming the file for one that cannot
/// be read or holds no triangles, and naming the scene for one of spheres or user primitives (the double path traces
/// triangle meshes only). The file's existence is the caller's check (FileNotFound, a CLI usage error).
NamedMeshD load_mesh_double(std::string_view spec, const DVec3& offset = {});

}  // namespace rayaccel
