// Conformance after Accelerator::update(): a closed mesh animated over several frames (a wave, a twist, a mirror that
// inverts every triangle, a tear that stretches half the mesh apart, a vertex gone NaN), every registered structure
// updated in place (refitted where supports_refit(), rebuilt otherwise) and checked against brute force on the same
// moved scene every frame, with validate() empty; also over caller buffers (buffers_changed()), and the rebuild a
// refitting structure must fall back to when a triangle left out of the build becomes valid.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "oracle.h"
#include "test_scenes.h"

namespace rayaccel::conformance {
namespace {

class Update : public ConformanceTest {};

/// Frame `frame` (1..5) of the animation of `rest`; each frame is a large move from the one before.
std::vector<Vec3> animate(const std::vector<Vec3>& rest, int frame) {
  std::vector<Vec3> out = rest;
  for (std::size_t i = 0; i < out.size(); ++i) {
    Vec3& v = out[i];
    switch (frame) {
      case 1:  // a wave
        v.y += 0.3f * std::sin(4.0f * v.x) * std::cos(3.0f * v.z);
        break;
      case 2: {  // a twist about y
        const float a = 1.5f * v.y, c = std::cos(a), s = std::sin(a);
        v = Vec3{c * v.x - s * v.z, v.y, s * v.x + c * v.z};
        break;
      }
      case 3:  // mirrored in x and moved: every triangle's orientation inverts
        v = Vec3{-0.7f * v.x + 2.0f, v.y, v.z};
        break;
      case 4:  // torn: the upper half moved far away, stretching the triangles across the tear
        if (v.y > 0.0f) v = Vec3{v.x + 3.0f, v.y * 2.0f, v.z - 1.0f};
        break;
      default:  // flattened, and one vertex non-finite (its triangles become invalid)
        v = Vec3{v.x, 0.05f * v.y, v.z};
        if (i == 7) v.x = std::numeric_limits<float>::quiet_NaN();
        break;
    }
  }
  return out;
}

std::vector<Ray> frame_rays(const Scene& scene, int frame) {
  std::vector<Ray> rays = random_rays(scene.bounds(), 300, 700 + static_cast<std::uint64_t>(frame));
  const std::vector<Ray> camera = camera_rays(scene.bounds(), 16, 12);
  rays.insert(rays.end(), camera.begin(), camera.end());
  return rays;
}

void expect_valid(const Accelerator& accel, const std::string& label) {
  const std::vector<std::string> problems = accel.validate();
  EXPECT_TRUE(problems.empty()) << label << ": " << problems.front();
}

TEST_P(Update, AnimatedMeshEveryFrameMatchesBruteForce) {
  const TriangleMesh mesh = closed_sphere_mesh(10, 14);
  Scene scene = Scene::from_mesh(mesh, "animated sphere");
  auto accel = build_checked(GetParam(), scene);
  const UpdateKind expected = accel->supports_refit() ? UpdateKind::refitted : UpdateKind::rebuilt;
  for (int frame = 1; frame <= 5; ++frame) {
    scene.set_vertices(animate(mesh.vertices, frame));
    const std::string label = "frame " + std::to_string(frame);
    EXPECT_EQ(accel->update(scene), expected) << label;
    expect_valid(*accel, label);
    expect_matches_brute_force(*accel, scene, frame_rays(scene, frame), label);
  }
}

TEST_P(Update, CallerBuffersChangedInPlace) {
  TriangleMesh mesh = closed_sphere_mesh(8, 10);
  const std::vector<Vec3> rest = mesh.vertices;
  MeshBuffers buffers;
  buffers.vertices = mesh.vertices.data();
  buffers.vertex_count = mesh.vertices.size();
  buffers.indices = mesh.triangles.data();
  buffers.triangle_count = mesh.triangles.size();
  Scene scene = Scene::from_buffers(buffers, "buffers");
  auto accel = build_checked(GetParam(), scene);
  for (int frame : {2, 3}) {
    const std::vector<Vec3> moved = animate(rest, frame);
    std::copy(moved.begin(), moved.end(), mesh.vertices.begin());  // in place: the scene reads these
    scene.buffers_changed();
    const std::string label = "buffers frame " + std::to_string(frame);
    accel->update(scene);
    expect_valid(*accel, label);
    expect_matches_brute_force(*accel, scene, frame_rays(scene, frame), label);
  }
}

TEST_P(Update, TriangleLeftOutOfTheBuildForcesRebuild) {
  TriangleMesh mesh = closed_sphere_mesh(8, 10);
  const std::vector<Vec3> rest = mesh.vertices;
  // Triangle 20 made zero-area (one vertex onto another): Scene leaves it out, so no structure holds it.
  const auto& t = mesh.triangles[20];
  mesh.vertices[t[2]] = mesh.vertices[t[1]];
  Scene scene = Scene::from_mesh(mesh, "degenerate at build");
  ASSERT_GE(scene.degenerate_count(), 1u);
  auto accel = build_checked(GetParam(), scene);
  scene.set_vertices(rest);  // every triangle valid again
  ASSERT_EQ(scene.degenerate_count(), 0u);
  EXPECT_EQ(accel->update(scene), UpdateKind::rebuilt);
  expect_valid(*accel, "valid again");
  expect_matches_brute_force(*accel, scene, frame_rays(scene, 0), "valid again");
}

INSTANTIATE_TEST_SUITE_P(Conformance, Update, ::testing::ValuesIn(variant_specs()), spec_test_name);

}  // namespace
}  // namespace rayaccel::conformance
