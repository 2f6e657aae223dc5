// Mesh import in a build without assimp (RAYACCEL_WITH_ASSIMP=OFF): every file is refused with the reason, so
// only builtin: scenes and scenes made from the caller's own arrays load.
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/scene/import.h"

namespace rayaccel {

TriangleMesh import_mesh(const std::filesystem::path& path) {
  throw Error("cannot read mesh file '" + path.string() +
              "': this rayaccel was built without mesh import (RAYACCEL_WITH_ASSIMP=OFF); use a builtin: scene or "
              "build a Scene from your own arrays");
}

}  // namespace rayaccel
