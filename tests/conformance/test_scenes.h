// Small deterministic scenes and ray sets for the conformance suite: random soups, closed meshes (a tessellated
// sphere and a subdivided cube with shared vertices), axis-aligned quad lattices, degenerate and transformed
// geometry, and the seeded random, camera and adversarial rays fired at them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel::conformance {

/// A named scene plus the rays fired at it.
struct SceneCase {
  std::string name;
  Scene scene;
  std::vector<Ray> rays;
};

/// Deterministic 32-bit generator (PCG-style LCG + xorshift); same sequence on every platform, unlike std::
/// distributions.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed * 0x9E3779B97F4A7C15ull + 1) {}
  std::uint32_t next();
  /// Uniform in [0, 1).
  float uniform() { return static_cast<float>(next() >> 8) * 0x1p-24f; }
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n).
  std::uint32_t below(std::uint32_t n) { return next() % n; }
  Vec3 in_box(const AABB& box);
  Vec3 unit_vector();

 private:
  std::uint64_t state_;
};

// ---- Triangle meshes -------------------------------------------------------------------------------------------

/// `count` random triangles with vertices in [0, 1]^3 of edge length up to `size` (a few are long slivers).
TriangleMesh random_soup_mesh(std::uint32_t count, float size, std::uint64_t seed);
/// Closed UV sphere of radius 1 at the origin with shared vertices (one vertex per pole): every edge is shared by
/// exactly two triangles. `stacks` >= 2 rings of latitude, `slices` >= 3 of longitude.
TriangleMesh closed_sphere_mesh(int stacks, int slices);
/// Closed cube [-1, 1]^3, each face an n x n grid of quads (two triangles each) with vertices shared across faces.
/// Coordinates are dyadic (n a power of two) so edge midpoints are exact floats.
TriangleMesh closed_box_mesh(int n);
/// Unit quads (two triangles each) on the planes x = 0..n-1 and y = 0..n-1, covering [0, n-1] in the other two
/// axes: flat primitive boxes, shared edges, and many planes for axis-parallel rays to graze.
TriangleMesh quad_lattice_mesh(int n);
/// Every vertex mapped to p * scale + offset.
TriangleMesh transformed(TriangleMesh mesh, float scale, const Vec3& offset);

// ---- Rays ------------------------------------------------------------------------------------------------------

/// Seeded random rays about `box`: origins inside and outside it, directions uniform, aimed at the box, or
/// axis-aligned with +0 and -0 in the other components; some with a finite t_max or a positive t_min.
std::vector<Ray> random_rays(const AABB& box, std::size_t count, std::uint64_t seed);
/// Primary rays (width x height) of Camera::framing(box): a three-quarter view of the whole box.
std::vector<Ray> camera_rays(const AABB& box, int width, int height);
/// Axis-parallel rays and diagonals in axis planes, with every combination of +0 / -0 zero components, from every
/// origin in coords^3 (48 rays per origin). With coordinates on and between the planes of quad_lattice_mesh() or
/// closed_box_mesh(), they run exactly along, between and through the quads' planes, edges and vertices.
std::vector<Ray> axis_parallel_rays(const std::vector<float>& coords);
/// Rays whose origin lies on a triangle of the mesh (a vertex, an edge midpoint or an interior point), pointing
/// along and against the normal and in random directions.
std::vector<Ray> rays_from_surfaces(const Scene& scene, std::size_t count, std::uint64_t seed);
/// Rays with degenerate parameters: t_max = 0, t_min = t_max, t_min > t_max, negative and infinite t bounds,
/// NaN and Inf in origin, direction and t, zero directions of either sign. Aimed at `box`.
std::vector<Ray> degenerate_rays(const AABB& box);
/// True when PreparedRay(ray) is void (NaN / Inf / zero direction / empty interval): such rays must never hit.
bool is_bad_ray(const Ray& ray);

/// Rays from `origins` toward every vertex of the mesh and the midpoint of every edge (target - origin,
/// t_max = inf): through a closed mesh they must all hit.
std::vector<Ray> rays_to_vertices_and_edges(const TriangleMesh& mesh, const std::vector<Vec3>& origins);

// ---- Scene sets ------------------------------------------------------------------------------------------------

/// The small scenes the closest-hit and occlusion tests run over, each with ~1-2k seeded random rays.
const std::vector<SceneCase>& small_scene_cases();
/// Random spheres (overlapping, radii spread over two decades).
Scene random_sphere_scene(std::uint32_t count, std::uint64_t seed);
/// User primitives: spheres served through callbacks (with loose bounds), so structures see only the callbacks.
Scene user_sphere_scene(std::uint32_t count, std::uint64_t seed);

}  // namespace rayaccel::conformance
