// libFuzzer target: the .rays / .hits / .occ readers (scene/ray_io.h) on arbitrary file contents, written to a
// scratch file first (the readers take paths). Errors are expected; crashes and other exceptions are findings.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/scene/ray_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("rayaccel_fuzz_rays_" + std::to_string(::getpid()) + ".bin");
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    const auto rays = rayaccel::read_rays(file);
    if (rays.size() * sizeof(rayaccel::Ray) != size) __builtin_trap();
  } catch (const rayaccel::Error&) {
  }
  try {
    rayaccel::read_hits(file);
  } catch (const rayaccel::Error&) {
  }
  try {
    rayaccel::read_occlusion(file);
  } catch (const rayaccel::Error&) {
  }
  return 0;
}
