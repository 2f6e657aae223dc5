// Triangle4: four triangles in SoA form, the unit every SIMD triangle test reads (one block per four lanes).
#pragma once

#include <cstdint>

namespace rayaccel::simd {

/// Four triangles in SoA form: vertex[v][axis][lane]. Unused lanes hold prim kInvalidPrimId and a zero triangle
/// (a point, which the watertight test never hits).
struct alignas(16) Triangle4 {
  float vertex[3][3][4];
  std::uint32_t prim_id[4];
};
static_assert(sizeof(Triangle4) == 160, "Triangle4: 144 bytes of vertices + 16 bytes of ids");

}  // namespace rayaccel::simd
