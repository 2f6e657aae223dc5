// TriangleMeshD: the indexed triangle list of the double-precision path (vertices in double), in core so that the
// scene readers (scene/ply_reader.h) can fill it below the double/ layer that builds over it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "rayaccel/core/dvec3.h"

namespace rayaccel {

/// Indexed triangle list in double; primitive id = index into `triangles`.
struct TriangleMeshD {
  std::vector<DVec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

}  // namespace rayaccel
