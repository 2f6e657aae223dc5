// Default materials of the recursive renderer, chosen by scene name.
#include "rayaccel/render/materials.h"

#include <cmath>

#include "rayaccel/core/error.h"

namespace rayaccel {

void check_material(const Material& m) {
  const auto weight = [](float w, const char* name) {
    if (!(w >= 0.0f && w <= 1.0f)) throw Error(std::string("material: ") + name + " " + std::to_string(w) + " is not in [0, 1]");
  };
  weight(m.mirror, "mirror");
  weight(m.transmission, "transmission");
  if (m.mirror + m.transmission > 1.0f) throw Error("material: mirror + transmission exceeds 1");
  if (!(is_finite(m.diffuse) && m.diffuse.x >= 0.0f && m.diffuse.y >= 0.0f && m.diffuse.z >= 0.0f)) {
    throw Error("material: the diffuse colour must be finite and non-negative");
  }
  if (!(std::isfinite(m.ior) && m.ior > 0.0f)) throw Error("material: ior " + std::to_string(m.ior) + " is not > 0");
}

SceneMaterials default_materials(const Scene& scene, const MaterialOptions& options) {
  SceneMaterials materials;
  if (scene.name() == "sphereflake") {
    materials.table = {Material{{0.55f, 0.45f, 0.35f}, 0.6f, 0.0f, 1.5f}};
  } else if (scene.name() == "glass") {
    constexpr std::uint32_t kFloorTriangles = 2;
    if (scene.kind() != PrimitiveKind::triangles || scene.primitive_count() <= kFloorTriangles) {
      throw Error("materials: scene 'glass' is not the built-in glass scene (a floor of 2 triangles, then a ball)");
    }
    materials.table = {Material{{0.75f, 0.72f, 0.65f}}, Material{{0.0f, 0.0f, 0.0f}, 0.0f, 1.0f, 1.5f}};
    materials.prim_material.assign(scene.primitive_count(), 1);
    for (std::uint32_t id = 0; id < kFloorTriangles; ++id) materials.prim_material[id] = 0;
  } else {
    Material m;
    m.mirror = options.mirror;
    m.diffuse = m.diffuse * (1.0f - options.mirror);
    if (!(options.mirror >= 0.0f && options.mirror <= 1.0f)) {
      throw Error("materials: mirror " + std::to_string(options.mirror) + " is not in [0, 1]");
    }
    materials.table = {m};
  }
  for (const Material& m : materials.table) check_material(m);
  return materials;
}

}  // namespace rayaccel
