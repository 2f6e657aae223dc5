// flatten(): every instance's triangles in world space, vertices mapped in double and rounded once.
#include "rayaccel/instance/flatten.h"

#include <algorithm>
#include <string>

#include "rayaccel/core/error.h"

namespace rayaccel {

std::uint32_t FlattenedScene::instance_of(std::uint32_t flat_id) const {
  const auto it = std::upper_bound(first_prim.begin(), first_prim.end(), std::uint64_t{flat_id});
  return static_cast<std::uint32_t>(it - first_prim.begin()) - 1;
}

FlattenedScene flatten(const InstancedScene& scene) {
  for (std::uint32_t g = 0; g < scene.geometry_count(); ++g) {
    if (scene.geometry(g).kind() != PrimitiveKind::triangles) {
      throw Error("flatten: geometry " + std::to_string(g) + " is made of " + to_string(scene.geometry(g).kind()) +
                  ", not triangles");
    }
  }
  if (scene.flattened_primitive_count() >= kInvalidPrimId) {
    throw Error("flatten: " + std::to_string(scene.flattened_primitive_count()) +
                " triangles are more than one scene holds (2^32 - 1)");
  }
  FlattenedScene out;
  TriangleMesh mesh;
  std::uint64_t first = 0;
  for (const Instance& instance : scene.instances()) {
    out.first_prim.push_back(first);
    const Scene& geometry = scene.geometry(instance.geometry);
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    if (!geometry.borrows_buffers()) {
      // Shared vertices stay shared: each is mapped once.
      for (const Vec3& v : geometry.mesh().vertices) mesh.vertices.push_back(round_to_float(instance.transform.apply_point(v)));
      for (const auto& t : geometry.mesh().triangles) mesh.triangles.push_back({base + t[0], base + t[1], base + t[2]});
    } else {
      for (std::uint32_t id = 0; id < geometry.primitive_count(); ++id) {
        const std::uint32_t v = static_cast<std::uint32_t>(mesh.vertices.size());
        for (const Vec3& p : geometry.triangle(id)) mesh.vertices.push_back(round_to_float(instance.transform.apply_point(p)));
        mesh.triangles.push_back({v, v + 1, v + 2});
      }
    }
    first += geometry.primitive_count();
  }
  out.scene = Scene::from_mesh(std::move(mesh), "flattened");
  return out;
}

}  // namespace rayaccel
