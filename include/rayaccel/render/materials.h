// Materials of the recursive (Whitted) renderer: a diffuse colour, a mirror part and a dielectric part
// (Fresnel-weighted reflection and refraction, Whitted 1980), and which primitive gets which material.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rayaccel/scene/scene.h"
#include "rayaccel/core/vec3.h"

namespace rayaccel {

struct Material {
  Vec3 diffuse{0.7f, 0.7f, 0.7f};  ///< linear RGB albedo of the diffuse part
  float mirror = 0.0f;             ///< weight of the perfect mirror reflection, in [0, 1]
  float transmission = 0.0f;       ///< weight of the dielectric part (Fresnel reflection + refraction), in [0, 1]
  float ior = 1.5f;                ///< index of refraction of the dielectric (inside / outside), > 0
};

/// The material of every primitive: `table[prim_material[id]]`, or `table[0]` for every primitive when
/// prim_material is empty.
struct SceneMaterials {
  std::vector<Material> table{Material{}};
  std::vector<std::uint32_t> prim_material;

  const Material& of(std::uint32_t prim) const { return table[prim_material.empty() ? 0 : prim_material[prim]]; }
};

/// What --mirror asks for: every primitive of a mesh file becomes this much of a mirror (0: plain diffuse).
struct MaterialOptions {
  float mirror = 0.0f;
};

/// Materials for a scene by its name: the sphereflake is a reflective sphereflake (SPD "balls"); the "glass"
/// built-in is a glass ball (ior 1.5) on a diffuse floor (its first two triangles); every other scene is diffuse
/// grey, or options.mirror of a mirror. Throws Error for a mirror weight outside [0, 1], or a "glass" scene whose
/// layout is not the built-in's.
SceneMaterials default_materials(const Scene& scene, const MaterialOptions& options = {});

/// Throws Error naming the field when a material's weights are outside [0, 1], their sum exceeds 1, the diffuse
/// colour is negative or not finite, or ior is not a finite positive number.
void check_material(const Material& material);

}  // namespace rayaccel
