// Scenes for the BVH benchmarks: the shared meshes of shared/scenes with their standard 1024x1024 cameras.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rayaccel/core/error.h"
#include "rayaccel/scene/scene.h"
#include "rayaccel/scene/import.h"
#include "rayaccel/render/camera.h"

namespace rayaccel::bvh_bench {

inline std::filesystem::path scenes_dir() {
  if (const char* env = std::getenv("RAYACCEL_SCENES")) return env;
  return std::filesystem::path(__FILE__).parent_path() / ".." / ".." / "shared" / "scenes";
}

struct BenchScene {
  Scene scene;
  std::vector<Ray> primary;  ///< 1024 x 1024 rays of the standard camera
};

/// Loads a shared scene once and keeps it; nullptr when the file is missing.
inline const BenchScene* shared_scene(const std::string& name) {
  static std::map<std::string, std::unique_ptr<BenchScene>> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second.get();
  const auto path = scenes_dir() / (name + ".ply");
  TriangleMesh mesh;
  try {
    mesh = import_mesh(path);
  } catch (const Error&) {
    return (cache[name] = nullptr).get();
  }
  std::unique_ptr<BenchScene> loaded;
  const auto camera = standard_camera(path);
  if (!mesh.triangles.empty() && camera) {
    loaded = std::make_unique<BenchScene>();
    loaded->scene = Scene::from_mesh(std::move(mesh), name);
    constexpr int kSize = 1024;
    loaded->primary.reserve(kSize * kSize);
    for (int y = 0; y < kSize; ++y) {
      for (int x = 0; x < kSize; ++x) loaded->primary.push_back(camera->primary_ray(x, y, kSize, kSize));
    }
  }
  return (cache[name] = std::move(loaded)).get();
}

}  // namespace rayaccel::bvh_bench
