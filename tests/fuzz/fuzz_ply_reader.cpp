// libFuzzer target: the PLY reader (scene/ply_reader.h) on arbitrary bytes. Any outcome but a mesh whose indices
// are in range or an Error is a finding (crash, hang, sanitizer report, other exception).
#include <cstddef>
#include <cstdint>
#include <span>

#include "rayaccel/core/error.h"
#include "rayaccel/scene/ply_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const rayaccel::TriangleMesh mesh =
        rayaccel::parse_ply(std::as_bytes(std::span(data, size)), "fuzz.ply");
    for (const auto& tri : mesh.triangles) {
      for (std::uint32_t i : tri) {
        if (i >= mesh.vertices.size()) __builtin_trap();
      }
    }
  } catch (const rayaccel::Error&) {
  }
  return 0;
}
