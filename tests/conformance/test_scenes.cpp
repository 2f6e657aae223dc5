// Generators of the conformance suite's small scenes and ray sets; everything is deterministic from its seed.
#include "test_scenes.h"

#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <utility>

#include "rayaccel/geometry/ray_sphere.h"
#include "rayaccel/render/camera.h"
#include "../float_specials.h"

namespace rayaccel::conformance {

namespace {

using test_values::kInf;
using test_values::kNaN;

AABB usable_box(const AABB& box) { return box.is_empty() ? AABB(Vec3{-1.0f}, Vec3{1.0f}) : box; }

void add_triangle(TriangleMesh& mesh, const Vec3& a, const Vec3& b, const Vec3& c) {
  const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), {a, b, c});
  mesh.triangles.push_back({base, base + 1, base + 2});
}

/// A zero component of the given sign.
float signed_zero(bool negative) { return negative ? -0.0f : 0.0f; }

}  // namespace

std::uint32_t Rng::next() {
  // splitmix64 (Steele, Lea, Flood 2014): a well-mixed 64-bit output from a Weyl sequence.
  state_ += 0x9E3779B97F4A7C15ull;
  std::uint64_t z = state_;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return static_cast<std::uint32_t>((z ^ (z >> 31)) >> 32);
}

Vec3 Rng::in_box(const AABB& box) {
  return {uniform(box.lo.x, box.hi.x), uniform(box.lo.y, box.hi.y), uniform(box.lo.z, box.hi.z)};
}

Vec3 Rng::unit_vector() {
  const float z = uniform(-1.0f, 1.0f);
  const float phi = uniform(0.0f, 2.0f * std::numbers::pi_v<float>);
  const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

TriangleMesh random_soup_mesh(std::uint32_t count, float size, std::uint64_t seed) {
  Rng rng(seed);
  TriangleMesh mesh;
  for (std::uint32_t i = 0; i < count; ++i) {
    const Vec3 c = rng.in_box(AABB(Vec3{0.0f}, Vec3{1.0f}));
    if (rng.below(20) == 0) {  // sliver: long and nearly collinear
      const Vec3 d = rng.unit_vector() * (3.0f * size);
      add_triangle(mesh, c, c + d, c + d * 0.5f + rng.unit_vector() * (size * 1e-3f));
    } else {
      add_triangle(mesh, c + rng.unit_vector() * (size * rng.uniform()),
                   c + rng.unit_vector() * (size * rng.uniform()), c + rng.unit_vector() * (size * rng.uniform()));
    }
  }
  return mesh;
}

TriangleMesh closed_sphere_mesh(int stacks, int slices) {
  TriangleMesh mesh;
  mesh.vertices.push_back({0.0f, 1.0f, 0.0f});
  for (int i = 1; i < stacks; ++i) {
    const double theta = std::numbers::pi * i / stacks;
    for (int j = 0; j < slices; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / slices;
      mesh.vertices.push_back({static_cast<float>(std::sin(theta) * std::cos(phi)),
                               static_cast<float>(std::cos(theta)),
                               static_cast<float>(std::sin(theta) * std::sin(phi))});
    }
  }
  const auto south = static_cast<std::uint32_t>(mesh.vertices.size());
  mesh.vertices.push_back({0.0f, -1.0f, 0.0f});
  auto ring = [&](int i, int j) { return static_cast<std::uint32_t>(1 + (i - 1) * slices + (j % slices)); };
  for (int j = 0; j < slices; ++j) {
    mesh.triangles.push_back({0, ring(1, j + 1), ring(1, j)});
    for (int i = 1; i + 1 < stacks; ++i) {
      mesh.triangles.push_back({ring(i, j), ring(i, j + 1), ring(i + 1, j)});
      mesh.triangles.push_back({ring(i, j + 1), ring(i + 1, j + 1), ring(i + 1, j)});
    }
    mesh.triangles.push_back({ring(stacks - 1, j), ring(stacks - 1, j + 1), south});
  }
  return mesh;
}

TriangleMesh closed_box_mesh(int n) {
  TriangleMesh mesh;
  std::map<std::array<int, 3>, std::uint32_t> index;
  auto vertex = [&](std::array<int, 3> k) {
    auto [it, inserted] = index.try_emplace(k, static_cast<std::uint32_t>(mesh.vertices.size()));
    if (inserted) {
      mesh.vertices.push_back({-1.0f + 2.0f * static_cast<float>(k[0]) / static_cast<float>(n),
                               -1.0f + 2.0f * static_cast<float>(k[1]) / static_cast<float>(n),
                               -1.0f + 2.0f * static_cast<float>(k[2]) / static_cast<float>(n)});
    }
    return it->second;
  };
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int side : {0, n}) {
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          std::array<int, 3> k00{}, k10{}, k11{}, k01{};
          for (auto* k : {&k00, &k10, &k11, &k01}) (*k)[a] = side;
          k00[b] = i, k00[c] = j;
          k10[b] = i + 1, k10[c] = j;
          k11[b] = i + 1, k11[c] = j + 1;
          k01[b] = i, k01[c] = j + 1;
          const std::uint32_t v00 = vertex(k00), v10 = vertex(k10), v11 = vertex(k11), v01 = vertex(k01);
          mesh.triangles.push_back({v00, v10, v11});
          mesh.triangles.push_back({v00, v11, v01});
        }
      }
    }
  }
  return mesh;
}

TriangleMesh quad_lattice_mesh(int n) {
  TriangleMesh mesh;
  for (int axis = 0; axis < 2; ++axis) {
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    for (int plane = 0; plane < n; ++plane) {
      const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          Vec3 p;
          p[axis] = static_cast<float>(plane);
          p[b] = static_cast<float>(i);
          p[c] = static_cast<float>(j);
          mesh.vertices.push_back(p);
        }
      }
      auto at = [&](int i, int j) { return base + static_cast<std::uint32_t>(i * n + j); };
      for (int i = 0; i + 1 < n; ++i) {
        for (int j = 0; j + 1 < n; ++j) {
          mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
          mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
      }
    }
  }
  return mesh;
}

TriangleMesh transformed(TriangleMesh mesh, float scale, const Vec3& offset) {
  for (Vec3& v : mesh.vertices) v = v * scale + offset;
  return mesh;
}

std::vector<Ray> random_rays(const AABB& scene_box, std::size_t count, std::uint64_t seed) {
  const AABB box = usable_box(scene_box);
  Rng rng(seed);
  const Vec3 center = box.center();
  const float radius = std::max(0.5f * length(box.extent()), 1e-30f);
  const Vec3 margin = box.extent() * 0.1f;
  const AABB inner(box.lo - margin, box.hi + margin);
  std::vector<Ray> rays(count);
  for (Ray& ray : rays) {
    ray.origin = rng.below(10) < 4 ? rng.in_box(inner) : center + rng.unit_vector() * (radius * rng.uniform(1.2f, 3.0f));
    const std::uint32_t kind = rng.below(10);
    Vec3 d;
    if (kind < 2) {  // along an axis, other components +0 or -0
      const std::uint32_t axis = rng.below(3);
      for (std::uint32_t a = 0; a < 3; ++a) d[a] = signed_zero(rng.below(2) == 1);
      d[axis] = rng.below(2) ? 1.0f : -1.0f;
    } else if (kind < 3) {  // diagonal in an axis plane, third component +0 or -0
      const std::uint32_t zero_axis = rng.below(3);
      for (std::uint32_t a = 0; a < 3; ++a) d[a] = rng.below(2) ? rng.uniform(0.2f, 1.0f) : -rng.uniform(0.2f, 1.0f);
      d[zero_axis] = signed_zero(rng.below(2) == 1);
    } else if (kind < 7) {  // toward a point of the box
      d = rng.in_box(box) - ray.origin;
      if (d == Vec3{}) d = {1.0f, 0.0f, 0.0f};
    } else {
      d = rng.unit_vector();
    }
    ray.direction = d * rng.uniform(0.5f, 2.0f);
    const float speed = length(ray.direction);
    // One ray in ten starts later along its line; one in ten earlier (a negative t_min: the segment reaches behind
    // the origin, which traversals must not assume away).
    const std::uint32_t start = rng.below(10);
    ray.t_min = start == 0 ? rng.uniform(0.0f, radius) / speed : start == 1 ? -rng.uniform(0.0f, radius) / speed : 0.0f;
    ray.t_max = rng.below(4) == 0 ? ray.t_min + rng.uniform(0.0f, 4.0f * radius) / speed : kInf;
  }
  return rays;
}

std::vector<Ray> camera_rays(const AABB& scene_box, int width, int height) {
  const CameraFrame frame = Camera::framing(usable_box(scene_box)).frame(width, height);
  std::vector<Ray> rays;
  rays.reserve(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) rays.push_back(frame.ray(x, y));
  }
  return rays;
}

std::vector<Ray> axis_parallel_rays(const std::vector<float>& coords) {
  std::vector<Vec3> directions;
  for (int axis = 0; axis < 3; ++axis) {
    for (int bits = 0; bits < 8; ++bits) {  // sign of the axis component, then signs of the two zeros
      Vec3 d;
      d[axis] = (bits & 1) ? -1.0f : 1.0f;
      d[(axis + 1) % 3] = signed_zero((bits & 2) != 0);
      d[(axis + 2) % 3] = signed_zero((bits & 4) != 0);
      directions.push_back(d);
    }
    for (int bits = 0; bits < 8; ++bits) {  // diagonal in the plane normal to `axis`, that axis's zero signed
      Vec3 d;
      d[axis] = signed_zero((bits & 1) != 0);
      d[(axis + 1) % 3] = (bits & 2) ? -1.0f : 1.0f;
      d[(axis + 2) % 3] = (bits & 4) ? -1.0f : 1.0f;
      directions.push_back(d);
    }
  }
  std::vector<Ray> rays;
  for (float x : coords) {
    for (float y : coords) {
      for (float z : coords) {
        for (const Vec3& d : directions) {
          Ray ray;
          ray.origin = {x, y, z};
          ray.direction = d;
          rays.push_back(ray);
        }
      }
    }
  }
  return rays;
}

std::vector<Ray> rays_from_surfaces(const Scene& scene, std::size_t count, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Ray> rays;
  if (scene.kind() != PrimitiveKind::triangles || scene.primitive_count() == 0) return rays;
  while (rays.size() < count) {
    const std::uint32_t id = rng.below(scene.primitive_count());
    if (!scene.is_valid(id)) continue;
    const auto& t = scene.triangle(id);
    const std::uint32_t corner = rng.below(3);
    Vec3 origin;
    switch (rng.below(3)) {
      case 0: origin = t[corner]; break;
      case 1: origin = (t[corner] + t[(corner + 1) % 3]) * 0.5f; break;
      default: {
        const float u = rng.uniform(), v = rng.uniform() * (1.0f - u);
        origin = t[0] * (1.0f - u - v) + t[1] * u + t[2] * v;
      }
    }
    const Vec3 normal = cross(t[1] - t[0], t[2] - t[0]);
    Vec3 d;
    switch (rng.below(4)) {
      case 0: d = normal; break;
      case 1: d = -normal; break;
      case 2: d = t[(corner + 1) % 3] - t[corner]; break;  // in the triangle's plane, along an edge
      default: d = rng.unit_vector();
    }
    if (d == Vec3{}) d = rng.unit_vector();
    Ray ray;
    ray.origin = origin;
    ray.direction = d;
    rays.push_back(ray);
  }
  return rays;
}

std::vector<Ray> degenerate_rays(const AABB& scene_box) {
  const AABB box = usable_box(scene_box);
  const Vec3 center = box.center();
  const Vec3 outside = center + Vec3{1.0f, 0.8f, 1.2f} * (length(box.extent()) + 1.0f);
  const Vec3 toward = center - outside;
  const float mid_t = 1.0f;  // `outside + toward` is the center
  std::vector<Ray> rays;
  auto add = [&](Vec3 o, Vec3 d, float t_min, float t_max) { rays.push_back(Ray{o, t_min, d, t_max}); };
  for (const Vec3& o : {outside, center}) {
    const Vec3 d = o == center ? Vec3{0.3f, -0.2f, 1.0f} : toward;
    // Interval edge cases.
    add(o, d, 0.0f, 0.0f);
    add(o, d, 0.0f, -0.0f);
    add(o, d, -0.0f, 0.0f);
    add(o, d, mid_t, mid_t);
    add(o, d, 0.5f * mid_t, 0.5f * mid_t);
    add(o, d, 2.0f * mid_t, mid_t);    // t_min > t_max
    add(o, d, -kInf, kInf);            // hits behind the origin count too
    add(o, d, -1e30f, 0.0f);           // only behind
    add(o, d, -kInf, -kInf);
    add(o, d, kInf, kInf);
    add(o, d, 0.0f, -kInf);
    add(o, d, 0.0f, std::numeric_limits<float>::max());
    add(o, d, std::numeric_limits<float>::denorm_min(), kInf);
    // NaN and Inf parameters.
    add(o, d, kNaN, kInf);
    add(o, d, 0.0f, kNaN);
    for (int a = 0; a < 3; ++a) {
      for (float bad : {kNaN, kInf, -kInf}) {
        Vec3 bo = o, bd = d;
        bo[a] = bad;
        bd[a] = bad;
        add(bo, d, 0.0f, kInf);
        add(o, bd, 0.0f, kInf);
      }
    }
    // Zero directions of either sign, and extreme but valid ones.
    add(o, Vec3{0.0f, 0.0f, 0.0f}, 0.0f, kInf);
    add(o, Vec3{-0.0f, -0.0f, -0.0f}, 0.0f, kInf);
    add(o, Vec3{0.0f, -0.0f, 0.0f}, 0.0f, kInf);
    add(o, d * 1e-30f, 0.0f, kInf);
    add(o, d * 1e30f, 0.0f, kInf);
    add(o, Vec3{std::numeric_limits<float>::denorm_min(), 0.0f, -0.0f}, 0.0f, kInf);
    add(o, Vec3{1e-38f, 1e-38f, 1e-38f}, 0.0f, kInf);
  }
  return rays;
}

bool is_bad_ray(const Ray& ray) { return PreparedRay(ray).is_void(); }

std::vector<Ray> rays_to_vertices_and_edges(const TriangleMesh& mesh, const std::vector<Vec3>& origins) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (const auto& tri : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  }
  std::vector<Vec3> targets(mesh.vertices);
  for (const auto& [a, b] : edges) targets.push_back((mesh.vertices[a] + mesh.vertices[b]) * 0.5f);
  std::vector<Ray> rays;
  for (const Vec3& o : origins) {
    for (const Vec3& target : targets) {
      Ray ray;
      ray.origin = o;
      ray.direction = target - o;
      rays.push_back(ray);
    }
  }
  return rays;
}

const std::vector<SceneCase>& small_scene_cases() {
  static const std::vector<SceneCase> all = [] {
  std::vector<SceneCase> cases;
  auto add = [&](std::string name, Scene scene, std::uint64_t seed) {
    scene.set_name(name);
    std::vector<Ray> rays = random_rays(scene.bounds(), 1200, seed);
    cases.push_back({std::move(name), std::move(scene), std::move(rays)});
  };
  add("soup", Scene::from_mesh(random_soup_mesh(2000, 0.12f, 1)), 11);
  add("sphere_mesh", Scene::from_mesh(closed_sphere_mesh(16, 32)), 12);
  add("box_mesh", Scene::from_mesh(closed_box_mesh(8)), 13);
  add("quad_lattice", Scene::from_mesh(quad_lattice_mesh(6)), 14);
  {
    // Invalid (NaN / Inf vertex) and zero-area triangles mixed into a soup.
    TriangleMesh mesh = random_soup_mesh(600, 0.2f, 2);
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      auto& v = mesh.vertices;
      const auto& tri = mesh.triangles[i];
      if (i % 7 == 3) v[tri[1]].y = (i % 2) ? kNaN : kInf;
      if (i % 11 == 5) v[tri[2]] = (v[tri[0]] + v[tri[1]]) * 0.5f;  // collinear
      if (i % 13 == 6) v[tri[1]] = v[tri[2]] = v[tri[0]];           // a point
    }
    add("soup_with_invalid", Scene::from_mesh(std::move(mesh)), 15);
  }
  return cases;
  }();
  return all;
}

Scene random_sphere_scene(std::uint32_t count, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Sphere> spheres(count);
  for (Sphere& s : spheres) {
    s.center = rng.in_box(AABB(Vec3{0.0f}, Vec3{1.0f}));
    s.radius = 0.004f * std::pow(20.0f, rng.uniform());
  }
  return Scene::from_spheres(std::move(spheres), "random_spheres");
}

Scene user_sphere_scene(std::uint32_t count, std::uint64_t seed) {
  auto spheres = std::make_shared<std::vector<Sphere>>(random_sphere_scene(count, seed).spheres());
  UserPrimitives prims;
  prims.count = count;
  prims.bounds = [spheres](std::uint32_t id) {
    const Sphere& s = (*spheres)[id];
    const Vec3 r{s.radius * 1.25f};  // loose on purpose: structures must not assume tight bounds
    return AABB(s.center - r, s.center + r);
  };
  prims.intersect = [spheres](std::uint32_t id, const PreparedRay& ray, Hit& hit) {
    const Sphere& s = (*spheres)[id];
    return intersect_sphere(ray, s.center, s.radius, id, hit);
  };
  prims.normal = [spheres](std::uint32_t id, const Vec3& p) { return p - (*spheres)[id].center; };
  return Scene::from_user(std::move(prims), "user_spheres");
}

}  // namespace rayaccel::conformance
