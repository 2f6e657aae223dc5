// A mesh file read as an instanced scene: each distinct mesh of the file one geometry, each node's reference to a
// mesh one instance with the node's accumulated transform (scene/import.h reads the hierarchy; import_mesh() would
// flatten it).
#pragma once

#include <filesystem>

#include "rayaccel/instance/instanced_scene.h"

namespace rayaccel {

/// Geometry g is the file's g-th mesh with triangles (named "<file stem>#g"); instance i is the i-th node reference
/// in scene-graph order, with instance_id i. Throws Error as import_mesh() does, and (naming the instance) for a
/// node transform that is singular or not finite.
InstancedScene import_instanced_scene(const std::filesystem::path& path);

}  // namespace rayaccel
