// Scenes for the BVH benchmarks: the shared PLY meshes (read directly: the fixed binary layout of
// shared/scenes/MANIFEST.md) with their standard cameras, and a wave-deformed grid for refit.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rayaccel/core/scene.h"
#include "rayaccel/render/camera.h"

namespace rayaccel::bvh_bench {

inline std::filesystem::path scenes_dir() {
  if (const char* env = std::getenv("RAYACCEL_SCENES")) return env;
  return std::filesystem::path(__FILE__).parent_path() / ".." / ".." / "shared" / "scenes";
}

/// Reads a MANIFEST-format PLY (binary little endian, float xyz, uchar-count int faces); empty mesh on failure.
inline TriangleMesh read_shared_ply(const std::filesystem::path& path) {
  TriangleMesh mesh;
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::size_t vertices = 0, faces = 0;
  while (std::getline(in, line) && line != "end_header") {
    if (line.rfind("element vertex ", 0) == 0) vertices = std::stoul(line.substr(15));
    if (line.rfind("element face ", 0) == 0) faces = std::stoul(line.substr(13));
  }
  if (!in) return mesh;
  mesh.vertices.resize(vertices);
  in.read(reinterpret_cast<char*>(mesh.vertices.data()), static_cast<std::streamsize>(vertices * sizeof(Vec3)));
  mesh.triangles.resize(faces);
  for (auto& t : mesh.triangles) {
    char record[13];
    in.read(record, sizeof record);
    std::memcpy(t.data(), record + 1, 12);
  }
  if (!in) return {};
  return mesh;
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
  TriangleMesh mesh = read_shared_ply(path);
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
