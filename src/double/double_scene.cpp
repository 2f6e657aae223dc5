// DoubleScene: checks and derived arrays (triangle vertices, outward-rounded float boxes).
#include "rayaccel/double/double_scene.h"

#include <cstdio>
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/core/ray_d.h"
#include "rayaccel/geometry/ray_box_d.h"

namespace rayaccel {
namespace {

/// Every digit a double needs to read back the same.
std::string number_text(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

}  // namespace

DoubleScene::DoubleScene(TriangleMeshD mesh) : mesh_(std::move(mesh)) {
  for (std::size_t i = 0; i < mesh_.vertices.size(); ++i) {
    const DVec3& p = mesh_.vertices[i];
    for (int a = 0; a < 3; ++a) {
      if (!in_double_domain(p[a])) {
        throw Error("double scene: vertex " + std::to_string(i) + " has coordinate " + "xyz"[a] + " = " +
                    number_text(p[a]) + ", outside the double domain (0 or 2^-64 <= |x| <= 2^64)");
      }
    }
  }
  const std::size_t n = mesh_.triangles.size();
  triangles_.resize(n);
  boxes_.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    const auto& idx = mesh_.triangles[t];
    for (int k = 0; k < 3; ++k) {
      if (idx[k] >= mesh_.vertices.size()) {
        throw Error("double scene: triangle " + std::to_string(t) + " has index " + std::to_string(idx[k]) +
                    ", but there are " + std::to_string(mesh_.vertices.size()) + " vertices");
      }
      triangles_[t][k] = mesh_.vertices[idx[k]];
    }
    const AABB box = anchored_float_box(triangles_[t], DVec3{});
    boxes_[t] = box;
    bounds_.extend(box);
  }
}

std::size_t DoubleScene::memory_bytes() const {
  return mesh_.vertices.size() * sizeof(DVec3) + mesh_.triangles.size() * sizeof(mesh_.triangles[0]) +
         triangles_.size() * sizeof(triangles_[0]) + boxes_.size() * sizeof(AABB);
}

TriangleMeshD to_double_mesh(const TriangleMesh& mesh, const DVec3& offset) {
  TriangleMeshD out;
  out.triangles = mesh.triangles;
  out.vertices.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) out.vertices.push_back(DVec3(v) + offset);
  return out;
}

TriangleMesh to_float_mesh(const TriangleMeshD& mesh) {
  TriangleMesh out;
  out.triangles = mesh.triangles;
  out.vertices.reserve(mesh.vertices.size());
  for (const DVec3& v : mesh.vertices) out.vertices.push_back(to_float(v));
  return out;
}

}  // namespace rayaccel
