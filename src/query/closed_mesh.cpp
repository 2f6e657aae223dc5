// Closedness of a triangle scene: edges keyed by their two vertex positions (smaller first), counted, and the odd
// counts reported.
#include "rayaccel/query/closed_mesh.h"

#include <algorithm>
#include <array>
#include <tuple>
#include <vector>

#include "rayaccel/core/error.h"

namespace rayaccel {

ClosedMeshReport check_closed(const Scene& scene) {
  if (scene.kind() != PrimitiveKind::triangles) {
    throw Error("closed-mesh check: '" + scene.name() + "' holds " + to_string(scene.kind()) + ", not triangles");
  }
  using Key = std::array<float, 6>;
  const auto key = [](const Vec3& a, const Vec3& b) {
    const auto as_tuple = [](const Vec3& p) { return std::make_tuple(p.x, p.y, p.z); };
    const bool a_first = as_tuple(a) < as_tuple(b);
    const Vec3& p = a_first ? a : b;
    const Vec3& q = a_first ? b : a;
    return Key{p.x, p.y, p.z, q.x, q.y, q.z};
  };
  std::vector<Key> edges;
  edges.reserve(3 * std::size_t(scene.valid_count()));
  for (std::uint32_t id = 0; id < scene.primitive_count(); ++id) {
    if (!scene.is_valid(id)) continue;
    const std::array<Vec3, 3> t = scene.triangle(id);
    for (int k = 0; k < 3; ++k) edges.push_back(key(t[k], t[(k + 1) % 3]));
  }
  std::sort(edges.begin(), edges.end());
  ClosedMeshReport report;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    ++report.edge_count;
    if ((j - i) % 2 == 1) ++report.boundary_edges;
    i = j;
  }
  return report;
}

}  // namespace rayaccel
