// The C API's scenes: meshes copied from the caller's arrays, merged into one Scene (with each mesh's geometry id) when
// the first structure is built over them.
#include <cstring>

#include "capi_handles.h"

using rayaccel::capi::Failure;
using rayaccel::capi::guarded;
using rayaccel::capi::require;

extern "C" rayaccel_status rayaccel_scene_new(rayaccel_scene** out) {
  return guarded("rayaccel_scene_new", [&] {
    require(out, "out");
    *out = nullptr;
    auto scene = std::make_unique<rayaccel_scene>();
    scene->state = std::make_shared<rayaccel::capi::SceneState>();
    *out = scene.release();
  });
}

extern "C" void rayaccel_scene_release(rayaccel_scene* scene) { delete scene; }

extern "C" rayaccel_status rayaccel_scene_add_mesh(rayaccel_scene* scene, const float* vertices, size_t vertex_count,
                                                   const uint32_t* indices, size_t triangle_count, uint32_t* geom_id) {
  return guarded("rayaccel_scene_add_mesh", [&] {
    require(scene, "scene");
    if (vertex_count > 0) require(vertices, "vertices");
    if (triangle_count > 0) require(indices, "indices");
    auto& state = *scene->state;
    const std::lock_guard lock(state.mutex);
    if (state.scene) {
      throw Failure{RAYACCEL_INVALID_OPERATION, "a structure was already built over the scene, which is now "
                                                "immutable (make a new scene)"};
    }
    const std::uint32_t geometry = state.geometries.geometry_count();
    if (vertex_count >= rayaccel::kInvalidPrimId || triangle_count >= rayaccel::kInvalidPrimId) {
      throw Failure{RAYACCEL_INVALID_ARGUMENT, "mesh " + std::to_string(geometry) + ": " +
                                                   std::to_string(vertex_count) + " vertices and " +
                                                   std::to_string(triangle_count) + " triangles, 2^32 - 1 or more"};
    }
    rayaccel::TriangleMesh mesh;
    mesh.vertices.resize(vertex_count);
    for (size_t i = 0; i < vertex_count; ++i) {
      mesh.vertices[i] = rayaccel::Vec3{vertices[3 * i], vertices[3 * i + 1], vertices[3 * i + 2]};
    }
    mesh.triangles.resize(triangle_count);
    for (size_t i = 0; i < triangle_count; ++i) {
      for (int k = 0; k < 3; ++k) {
        const uint32_t index = indices[3 * i + k];
        if (index >= vertex_count) {
          throw Failure{RAYACCEL_INVALID_ARGUMENT, "mesh " + std::to_string(geometry) + ": triangle " +
                                                       std::to_string(i) + " uses vertex index " +
                                                       std::to_string(index) + ", but the mesh has " +
                                                       std::to_string(vertex_count) + " vertices"};
        }
        mesh.triangles[i][k] = index;
      }
    }
    rayaccel::GeometryTable grown = state.geometries;  // checks the total before anything changes
    grown.add(static_cast<std::uint32_t>(triangle_count));
    state.meshes.push_back(std::move(mesh));
    state.geometries = std::move(grown);
    if (geom_id != nullptr) *geom_id = geometry;
  });
}

extern "C" rayaccel_status rayaccel_scene_geometry_count(const rayaccel_scene* scene, uint32_t* count) {
  return guarded("rayaccel_scene_geometry_count", [&] {
    require(scene, "scene");
    require(count, "count");
    const std::lock_guard lock(scene->state->mutex);
    *count = scene->state->geometries.geometry_count();
  });
}

extern "C" rayaccel_status rayaccel_scene_primitive_count(const rayaccel_scene* scene, uint32_t* count) {
  return guarded("rayaccel_scene_primitive_count", [&] {
    require(scene, "scene");
    require(count, "count");
    const std::lock_guard lock(scene->state->mutex);
    *count = scene->state->geometries.primitive_count();
  });
}

extern "C" rayaccel_status rayaccel_scene_set_mask(rayaccel_scene* scene, uint32_t geom_id, uint32_t mask) {
  return guarded("rayaccel_scene_set_mask", [&] {
    require(scene, "scene");
    auto& state = *scene->state;
    const std::lock_guard lock(state.mutex);
    if (geom_id >= state.geometries.geometry_count()) {
      throw Failure{RAYACCEL_INVALID_ARGUMENT, "geometry " + std::to_string(geom_id) +
                                                   " does not exist (the scene has " +
                                                   std::to_string(state.geometries.geometry_count()) + ")"};
    }
    if (state.masks.size() <= geom_id) state.masks.resize(state.geometries.geometry_count(), ~0u);
    state.masks[geom_id] = mask;
  });
}
