// Unit tests of the watertight kernel on triangles tiny across the ray but not along it (issue #19): edge functions
// near or below float's normal range must neither underflow t (a hit at t = -0 for a ray whose exact t is -1e-7,
// below t_min) nor lose the hit.
#include <gtest/gtest.h>

#include <cmath>

#include "rayaccel/accel/registry.h"
#include "rayaccel/scene/scene.h"
#include "rayaccel/geometry/ray_triangle.h"

namespace rayaccel {
namespace {

TEST(TinyTriangle, DistanceAlongTheRayIsKeptWhenEdgeFunctionsAreTiny) {
  for (float size : {1e-17f, 1e-18f, 3e-19f, 1e-19f, 3e-20f, 1e-21f}) {
    for (float height : {1e-7f, 1e-5f, 1e-3f}) {
      TriangleMesh mesh;
      mesh.vertices = {{0.0f, 0.0f, 0.0f}, {size, 0.0f, 0.0f}, {0.0f, size, 0.0f}};
      mesh.triangles = {{0, 1, 2}};
      const Scene scene = Scene::from_mesh(mesh, "tiny triangle");
      auto brute = make_accelerator("brute_force");
      brute->build(scene);
      // Above the triangle, leaving it: exact t = -height, below t_min = -height / 100.
      Ray away;
      away.origin = {0.2f * size, 0.2f * size, height};
      away.direction = {0.0f, 0.0f, 1.0f};
      away.t_min = -0.01f * height;
      const Hit behind = brute->intersect(away);
      EXPECT_FALSE(behind.found()) << "size " << size << " height " << height << ": hit at t = " << behind.t;
      EXPECT_FALSE(brute->occluded(away)) << "size " << size << " height " << height;
      // Toward it: exact t = height.
      Ray toward = away;
      toward.direction = {0.0f, 0.0f, -1.0f};
      toward.t_min = 0.0f;
      const Hit hit = brute->intersect(toward);
      ASSERT_TRUE(hit.found()) << "size " << size << " height " << height;
      EXPECT_NEAR(hit.t, height, 1e-6f * height) << "size " << size;
      EXPECT_NEAR(hit.u, 0.2f, 1e-5f) << "size " << size;
      EXPECT_NEAR(hit.v, 0.2f, 1e-5f) << "size " << size;
    }
  }
}

}  // namespace
}  // namespace rayaccel
