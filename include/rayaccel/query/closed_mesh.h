// Whether a triangle scene is closed: every edge, with vertices matched by position, shared by an even number of
// valid triangles. On such a mesh (a boundary mod 2) a line that starts and ends outside crosses the surface an even
// number of times, which the crossing-parity inside test relies on.
#pragma once

#include <cstddef>

#include "rayaccel/scene/scene.h"

namespace rayaccel {

struct ClosedMeshReport {
  std::size_t edge_count = 0;      ///< distinct edges of the valid triangles
  std::size_t boundary_edges = 0;  ///< edges used by an odd number of triangles (0 for a closed mesh)
  bool closed() const { return boundary_edges == 0 && edge_count > 0; }
};

/// Counts the edges of a triangle scene's valid triangles used an odd number of times. Throws Error for a scene
/// that is not made of triangles.
ClosedMeshReport check_closed(const Scene& scene);

}  // namespace rayaccel
