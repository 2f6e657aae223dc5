// A closed, outward-oriented, non-convex test solid made of unit voxels (a staircase with a tunnel through it), with
// integer vertices shared between faces: rays and points at its vertices, edges and faces are exact floats, and
// whether a point is inside is known in closed form from the voxel occupancy.
#pragma once

#include <array>
#include <cmath>
#include <map>

#include "rayaccel/core/primitives.h"
#include "rayaccel/core/vec3.h"

namespace rayaccel::testing {

/// Voxels of [0, 4)^3: a staircase (i + j + k <= 4) with a tunnel along y through voxels (1, *, 1).
inline bool voxel_occupied(int i, int j, int k) {
  if (i < 0 || j < 0 || k < 0 || i >= 4 || j >= 4 || k >= 4) return false;
  return i + j + k <= 4 && !(i == 1 && k == 1);
}

/// The boundary of the voxel set: every unit face between an occupied voxel and an empty one, as two triangles
/// (diagonals alternating), counter-clockwise seen from outside.
inline TriangleMesh voxel_shape_mesh() {
  TriangleMesh mesh;
  std::map<std::array<int, 3>, std::uint32_t> index;
  const auto vertex = [&](const std::array<int, 3>& k) {
    auto [it, inserted] = index.try_emplace(k, static_cast<std::uint32_t>(mesh.vertices.size()));
    if (inserted) mesh.vertices.push_back({float(k[0]), float(k[1]), float(k[2])});
    return it->second;
  };
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      for (int k = 0; k < 4; ++k) {
        if (!voxel_occupied(i, j, k)) continue;
        const std::array<int, 3> cell{i, j, k};
        for (int a = 0; a < 3; ++a) {
          for (int side : {0, 1}) {
            std::array<int, 3> neighbour = cell;
            neighbour[a] += side ? 1 : -1;
            if (voxel_occupied(neighbour[0], neighbour[1], neighbour[2])) continue;
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            std::array<int, 3> q[4];
            for (int n = 0; n < 4; ++n) {
              q[n] = cell;
              q[n][a] += side;
              q[n][b] += (n == 1 || n == 2) ? 1 : 0;
              q[n][c] += (n >= 2) ? 1 : 0;
            }
            // (b, c) counter-clockwise has normal +a: kept for the + side, reversed for the - side.
            std::uint32_t v[4] = {vertex(q[0]), vertex(q[1]), vertex(q[2]), vertex(q[3])};
            if (!side) std::swap(v[1], v[3]);
            if ((i + j + k) % 2 == 0) {
              mesh.triangles.push_back({v[0], v[1], v[2]});
              mesh.triangles.push_back({v[0], v[2], v[3]});
            } else {
              mesh.triangles.push_back({v[0], v[1], v[3]});
              mesh.triangles.push_back({v[1], v[2], v[3]});
            }
          }
        }
      }
    }
  }
  return mesh;
}

/// The fraction of the small ball about p that is inside the solid: 0 or 1 away from the surface, 1/2 on a face,
/// k/4 on an edge and k/8 at a vertex (k occupied voxels around it): the generalised winding number there.
inline double voxel_inside_fraction(const Vec3& p) {
  // The voxels whose closure holds p: along an axis, one voxel for a non-integer coordinate, two for an integer one.
  int lo[3], count[3];
  for (int a = 0; a < 3; ++a) {
    const float x = p[a];
    const float f = std::floor(x);
    lo[a] = static_cast<int>(f) - (x == f ? 1 : 0);
    count[a] = x == f ? 2 : 1;
  }
  int occupied = 0, total = 0;
  for (int i = 0; i < count[0]; ++i) {
    for (int j = 0; j < count[1]; ++j) {
      for (int k = 0; k < count[2]; ++k) {
        ++total;
        occupied += voxel_occupied(lo[0] + i, lo[1] + j, lo[2] + k) ? 1 : 0;
      }
    }
  }
  return double(occupied) / double(total);
}

}  // namespace rayaccel::testing
