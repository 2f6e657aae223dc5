// Internal to src/scene: the procedural generators behind the built-in scenes, a portable seeded random source
// (SplitMix64, Steele, Lea, Flood 2014) and mesh concatenation. Every generator is deterministic.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "rayaccel/core/primitives.h"
#include "rayaccel/core/vec3.h"

namespace rayaccel::procedural {

/// SplitMix64: the same sequence on every platform (std distributions are implementation-defined, so none are used).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform in the cube [-1, 1)^3.
  Vec3 in_cube() {
    const double x = uniform(-1.0, 1.0), y = uniform(-1.0, 1.0), z = uniform(-1.0, 1.0);
    return {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)};
  }
  /// Uniform unit vector (rejection sampling in the unit ball, in double).
  Vec3 unit_vector() {
    for (;;) {
      const double x = uniform(-1.0, 1.0), y = uniform(-1.0, 1.0), z = uniform(-1.0, 1.0);
      const double len2 = x * x + y * y + z * z;
      if (len2 > 1e-6 && len2 <= 1.0) {
        const double inv = 1.0 / std::sqrt(len2);
        return {static_cast<float>(x * inv), static_cast<float>(y * inv), static_cast<float>(z * inv)};
      }
    }
  }

 private:
  std::uint64_t state_;
};

/// Appends `src` to `dst`, each vertex mapped to p * scale + offset (scale > 0 keeps the winding).
void append_mesh(TriangleMesh& dst, const TriangleMesh& src, float scale = 1.0f, Vec3 offset = {});

/// Haines' sphereflake (SPD "balls"): a sphere of `radius` at the origin carrying 9 children of a third of its
/// radius (6 round its equator, 3 above), recursively; level 0 is the single sphere, level L has sum 9^i spheres.
std::vector<Sphere> sphereflake(int level, float radius);

/// Fractal mountain (SPD "mountain") by midpoint displacement (diamond-square, Fournier, Fussell, Carpenter 1982)
/// on a (2^level + 1)^2 height grid over [-size/2, size/2]^2 in the XZ plane, Y up; 2 * 4^level triangles facing
/// +Y. The first displacement is at most height * size and shrinks by `roughness` per level.
TriangleMesh mountain(int level, float size, float height, float roughness, std::uint64_t seed);

/// Height of the mountain's highest vertex within `radius` (in XZ) of (x, z); -inf when there is none.
float highest_point_near(const TriangleMesh& mountain, float x, float z, float radius);

/// Sierpinski tetrahedron: a regular tetrahedron of edge `edge` standing on y = 0 centred on the Y axis, replaced
/// `level` times by its 4 corner half-size copies; 4^level tetrahedra of 4 outward faces each (vertices are shared
/// within a tetrahedron only).
TriangleMesh sierpinski(int level, float edge);

/// Closed (p, q) torus knot tube about the origin, lying in the XZ plane (curve radius 1..3 and height -1..1,
/// then the tube, all times `scale`): `segments` rings of `tube_segments` vertices, indices wrapping in both
/// directions, so the surface is closed with outward winding.
TriangleMesh torus_knot(int p, int q, int segments, int tube_segments, float tube_radius, float scale);

/// A sparse stadium of extent `size`: a flat square field at y = 0 and `sectors` wedges of tiered stands in a ring.
TriangleMesh stadium(float size, int sectors, int tiers);

/// `count` triangles of length 2 * half_length and width half_length * 2 / aspect, random centres in [-1, 1)^3 and
/// random directions.
TriangleMesh slivers(int count, float half_length, float aspect, std::uint64_t seed);

/// `count` independent triangles: random centres in [-1, 1)^3, each vertex displaced by up to `size` per axis.
TriangleMesh soup(int count, float size, std::uint64_t seed);

/// Subdivided icosahedron projected onto a sphere of `radius` at the origin: 20 * 4^level triangles, outward
/// winding, every edge shared by exactly two triangles through the same vertex indices (watertight).
TriangleMesh icosphere(int level, float radius);

}  // namespace rayaccel::procedural
