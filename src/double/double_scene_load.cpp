// Scene specs read in double: PLY files by the double PLY reader, everything else through load_scene().
#include "rayaccel/double/double_scene_load.h"

#include <array>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <span>

#include "rayaccel/core/error.h"
#include "rayaccel/double/double_scene.h"
#include "rayaccel/scene/import.h"
#include "rayaccel/scene/ply_reader.h"

namespace rayaccel {

namespace {

/// True when the file starts like a PLY file.
bool is_ply_file(const std::string& path) {
  std::array<std::byte, 5> head{};
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(head.data()), head.size());
  return looks_like_ply(std::span<const std::byte>(head.data(), static_cast<std::size_t>(in.gcount())));
}

}  // namespace

NamedMeshD load_mesh_double(std::string_view spec, const DVec3& offset) {
  const std::string path(spec);
  if (path.rfind("builtin:", 0) != 0 && is_ply_file(path)) {
    NamedMeshD out{read_ply_double(path), std::filesystem::path(path).stem().string()};
    if (out.mesh.triangles.empty()) throw Error("mesh file '" + path + "' has no triangles");
    for (DVec3& v : out.mesh.vertices) v = v + offset;
    return out;
  }
  const Scene scene = load_scene(spec);
  if (scene.kind() != PrimitiveKind::triangles) {
    throw Error("scene '" + path + "' holds " + to_string(scene.kind()) +
                "; the double path traces triangle meshes only");
  }
  return {to_double_mesh(scene.mesh(), offset), scene.name()};
}

}  // namespace rayaccel
