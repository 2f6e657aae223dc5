// The C API's handles behind its opaque types, and guarded(): the one place a C++ exception becomes a status code and
// this thread's error message (no exception crosses the C boundary).
#pragma once

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/core/error.h"
#include "rayaccel/rayaccel_c.h"
#include "rayaccel/scene/geometry_table.h"

namespace rayaccel::capi {

/// Meshes collected by rayaccel_scene_add_mesh, merged into one Scene when the first structure is built over them.
struct SceneState {
  std::mutex mutex;  // guards meshes and scene while a scene is being filled or committed
  std::vector<TriangleMesh> meshes;
  GeometryTable geometries;
  std::vector<std::uint32_t> masks;  // per geometry (rayaccel_scene_set_mask); all ones until set
  std::optional<Scene> scene;  // set once; then immutable, read by every structure built over it
};

/// A failure with its own status code (the library's Error is RAYACCEL_INVALID_ARGUMENT).
struct Failure {
  rayaccel_status status;
  std::string message;
};

/// Sets this thread's last error to `message` (or clears it for RAYACCEL_OK) and returns `status`.
rayaccel_status set_status(rayaccel_status status, const char* message);

/// Runs body(), turning every exception into a status and this thread's message; RAYACCEL_OK clears the message.
template <class Body>
rayaccel_status guarded(const char* function, Body&& body) noexcept {
  try {
    body();
    return set_status(RAYACCEL_OK, "");
  } catch (const Failure& f) {
    return set_status(f.status, (std::string(function) + ": " + f.message).c_str());
  } catch (const Error& e) {
    return set_status(RAYACCEL_INVALID_ARGUMENT, (std::string(function) + ": " + e.what()).c_str());
  } catch (const std::bad_alloc&) {
    return set_status(RAYACCEL_OUT_OF_MEMORY, (std::string(function) + ": out of memory").c_str());
  } catch (const std::exception& e) {
    return set_status(RAYACCEL_INTERNAL_ERROR, (std::string(function) + ": " + e.what()).c_str());
  } catch (...) {
    return set_status(RAYACCEL_INTERNAL_ERROR, (std::string(function) + ": unknown exception").c_str());
  }
}

/// Throws Failure(RAYACCEL_INVALID_ARGUMENT) naming `name` when `pointer` is null.
inline void require(const void* pointer, const char* name) {
  if (pointer == nullptr) throw Failure{RAYACCEL_INVALID_ARGUMENT, std::string(name) + " is null"};
}

}  // namespace rayaccel::capi

struct rayaccel_scene {
  std::shared_ptr<rayaccel::capi::SceneState> state;
};

struct rayaccel_accel {
  std::shared_ptr<rayaccel::capi::SceneState> scene;  // keeps the scene alive, and maps hits to (geom_id, prim_id)
  std::unique_ptr<rayaccel::Accelerator> structure;
};
