// libFuzzer target: the saved-BVH loader (bvh/bvh_io.h). The input is a file body; before it is written, its
// header's scene fields and its checksum are made to match the fixed scene, so the fuzzer reaches the structural
// checks behind them (node links, leaf ranges, bounds) instead of stopping at the checksum. A file that loads must
// validate and trace without a fault.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "rayaccel/bv/aabb_volume.h"
#include "rayaccel/bvh/bvh.h"
#include "rayaccel/bvh/bvh_file.h"
#include "rayaccel/bvh/bvh_io.h"
#include "rayaccel/core/error.h"

namespace {

const rayaccel::Scene& fixed_scene() {
  static const rayaccel::Scene scene = [] {
    rayaccel::TriangleMesh mesh;
    for (std::uint32_t i = 0; i < 8; ++i) {
      const float x = float(i);
      mesh.vertices.push_back({x, 0.0f, 0.0f});
      mesh.vertices.push_back({x + 1.0f, 0.0f, 0.5f});
      mesh.vertices.push_back({x, 1.0f, 1.0f});
      mesh.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
    }
    return rayaccel::Scene::from_mesh(mesh, "fuzz");
  }();
  return scene;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rayaccel;
  static const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("rayaccel_fuzz_bvh_" + std::to_string(::getpid()) + ".bvh");
  const Scene& scene = fixed_scene();
  std::vector<std::byte> bytes(reinterpret_cast<const std::byte*>(data), reinterpret_cast<const std::byte*>(data) + size);
  if (bytes.size() >= sizeof(BvhFileHeader) + 8) {
    BvhFileHeader h;
    std::memcpy(&h, bytes.data(), sizeof h);
    std::memcpy(h.magic, kBvhFileMagic, sizeof h.magic);
    h.version = kBvhFileVersion;
    h.scene_fingerprint = bvh_scene_fingerprint(scene);
    h.primitive_count = scene.primitive_count();
    std::memcpy(bytes.data(), &h, sizeof h);
    const std::uint64_t sum = bvh_checksum(std::span(bytes).first(bytes.size() - 8));
    std::memcpy(bytes.data() + bytes.size() - 8, &sum, 8);
  }
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  }
  Bvh<AabbVolume> bvh;
  try {
    bvh.load(file, scene);
  } catch (const Error&) {
    return 0;
  }
  // Loaded: it must be a valid tree, and tracing it must be safe.
  if (!bvh.validate().empty()) __builtin_trap();
  Ray ray;
  ray.origin = {4.0f, 0.3f, -5.0f};
  ray.direction = {0.01f, 0.02f, 1.0f};
  (void)bvh.intersect(ray);
  (void)bvh.occluded(ray);
  return 0;
}
