// import_instanced_scene(): the file's mesh hierarchy (scene/import.h) turned into geometries and instances.
#include "rayaccel/instance/import_instanced.h"

#include <string>
#include <utility>

#include "rayaccel/scene/import.h"

namespace rayaccel {

InstancedScene import_instanced_scene(const std::filesystem::path& path) {
  MeshHierarchy hierarchy = import_mesh_hierarchy(path);
  InstancedScene scene;
  const std::string stem = path.stem().string();
  for (std::size_t g = 0; g < hierarchy.meshes.size(); ++g) {
    scene.add_geometry(Scene::from_mesh(std::move(hierarchy.meshes[g]), stem + "#" + std::to_string(g)));
  }
  for (const MeshHierarchy::Placement& placement : hierarchy.placements) {
    Affine3 transform;
    transform.m = placement.transform;
    scene.add_instance(placement.mesh, transform);
  }
  return scene;
}

}  // namespace rayaccel
