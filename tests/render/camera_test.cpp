// Tests of the pinhole camera (convention of shared/scenes/MANIFEST.md), framing, and standard cameras.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "../shared_scenes.h"
#include "rayaccel/core/error.h"
#include "rayaccel/render/camera.h"

namespace rayaccel {
namespace {

float angle_between(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(dot(normalize(a), normalize(b)), -1.0f, 1.0f));
}

float radians(float degrees) { return degrees * std::numbers::pi_v<float> / 180.0f; }

TEST(Camera, CenterRayLooksAtTarget) {
  Camera cam;
  cam.eye = {3.0f, -2.0f, 7.0f};
  cam.at = {-1.0f, 4.0f, 0.5f};
  cam.up = {0.0f, 1.0f, 0.0f};
  cam.fov_degrees = 50.0f;
  const Ray r = cam.primary_ray(50, 30, 101, 61);  // odd sizes: pixel (50, 30) is the exact center
  const Vec3 expected = normalize(cam.at - cam.eye);
  EXPECT_EQ(r.origin, cam.eye);
  EXPECT_NEAR(r.direction.x, expected.x, 1e-6f);
  EXPECT_NEAR(r.direction.y, expected.y, 1e-6f);
  EXPECT_NEAR(r.direction.z, expected.z, 1e-6f);
  EXPECT_NEAR(length(r.direction), 1.0f, 1e-6f);
  EXPECT_EQ(r.t_min, 0.0f);
  EXPECT_TRUE(std::isinf(r.t_max));
}

TEST(Camera, RightIsForwardCrossUpAndRowZeroIsTop) {
  Camera cam;
  cam.eye = {0.0f, 0.0f, 5.0f};
  cam.at = {0.0f, 0.0f, 0.0f};
  cam.up = {0.0f, 1.0f, 0.0f};
  // forward = -z, so image x = cross(-z, +y) = +x and image y = +y.
  const Ray right_edge = cam.primary_ray(62, 31, 63, 63);
  const Ray left_edge = cam.primary_ray(0, 31, 63, 63);
  const Ray top_row = cam.primary_ray(31, 0, 63, 63);
  const Ray bottom_row = cam.primary_ray(31, 62, 63, 63);
  EXPECT_GT(right_edge.direction.x, 0.1f);
  EXPECT_LT(left_edge.direction.x, -0.1f);
  EXPECT_NEAR(right_edge.direction.y, 0.0f, 1e-6f);
  EXPECT_GT(top_row.direction.y, 0.1f);
  EXPECT_LT(bottom_row.direction.y, -0.1f);
  EXPECT_NEAR(top_row.direction.x, 0.0f, 1e-6f);

  // A tilted camera: the frame follows normalize(cross(forward, up)) and the orthogonalized up.
  cam.eye = {2.0f, 3.0f, -4.0f};
  cam.at = {-1.0f, 0.5f, 1.0f};
  cam.up = {0.2f, 1.0f, 0.1f};
  const CameraFrame f = cam.frame(64, 64);
  const Vec3 forward = normalize(cam.at - cam.eye);
  const Vec3 right = normalize(cross(forward, cam.up));
  EXPECT_NEAR(dot(f.right, right), 1.0f, 1e-6f);
  EXPECT_NEAR(dot(f.up, cam.up), length(cam.up - forward * dot(cam.up, forward)), 1e-5f);
  EXPECT_NEAR(dot(f.up, forward), 0.0f, 1e-6f);
  const Ray px_right = f.ray(63, 32);
  const Ray px_top = f.ray(32, 0);
  EXPECT_GT(dot(px_right.direction, right), 0.3f);
  EXPECT_GT(dot(px_top.direction, f.up), 0.3f);
}

TEST(Camera, FieldOfViewEdgeRaysHaveTheRightAngle) {
  Camera cam;
  cam.eye = {1.0f, 2.0f, 3.0f};
  cam.at = {1.0f, 2.0f, -10.0f};
  cam.fov_degrees = 60.0f;
  const int w = 200, h = 100;
  const Vec3 forward{0.0f, 0.0f, -1.0f};
  const float half = radians(30.0f);
  // Pixel centers sit half a pixel inside the edges: the top row's angle is atan((1 - 1/h) tan(fov/2)).
  const Ray top = cam.primary_ray(w / 2, 0, w, h);
  const Ray top_left_center_column = cam.primary_ray(0, h / 2, w, h);
  const float expected_vertical = std::atan((1.0f - 1.0f / h) * std::tan(half));
  const float expected_horizontal = std::atan((1.0f - 1.0f / w) * std::tan(half) * w / h);
  // Column w/2 and row h/2 are half a pixel off the center line: use the angle in the relevant plane only.
  EXPECT_NEAR(std::atan2(top.direction.y, -top.direction.z), expected_vertical, 1e-5f);
  EXPECT_NEAR(std::atan2(-top_left_center_column.direction.x, -top_left_center_column.direction.z),
              expected_horizontal, 1e-5f);
  // The full vertical field of view between the top and bottom pixel edges is fov: extrapolate from centers.
  const Ray top_center = cam.primary_ray(w / 2, 0, w, h);
  const Ray bottom_center = cam.primary_ray(w / 2, h - 1, w, h);
  const float spread = std::atan2(top_center.direction.y, -top_center.direction.z) -
                       std::atan2(bottom_center.direction.y, -bottom_center.direction.z);
  EXPECT_NEAR(spread, 2.0f * expected_vertical, 1e-5f);
  EXPECT_LT(angle_between(cam.primary_ray(w / 2, h / 2, w, h).direction, forward), radians(0.5f));
}

TEST(Camera, DegenerateCamerasGiveFiniteRays) {
  Camera same_point;
  same_point.eye = same_point.at = {1.0f, 1.0f, 1.0f};
  Camera up_along_view;
  up_along_view.eye = {0.0f, 5.0f, 0.0f};
  up_along_view.at = {0.0f, 0.0f, 0.0f};
  up_along_view.up = {0.0f, 1.0f, 0.0f};
  for (const Camera& cam : {same_point, up_along_view}) {
    const Ray r = cam.primary_ray(3, 4, 8, 8);
    EXPECT_TRUE(is_finite(r.direction));
    EXPECT_NEAR(length(r.direction), 1.0f, 1e-6f);
  }
  EXPECT_THROW(Camera{}.primary_ray(0, 0, 0, 8), Error);
}

TEST(Camera, FramingSeesTheWholeBox) {
  const AABB boxes[] = {
      AABB({-1.0f, -2.0f, -3.0f}, {4.0f, 5.0f, 6.0f}),
      AABB({100.0f, 0.0f, -5.0f}, {120.0f, 0.0f, 5.0f}),  // flat
      AABB({1e6f, 1e6f, 1e6f}, {1e6f + 1.0f, 1e6f + 2.0f, 1e6f + 3.0f}),
  };
  for (const AABB& box : boxes) {
    const Camera cam = Camera::framing(box);
    const CameraFrame f = cam.frame(64, 64);
    EXPECT_FALSE(box.contains(cam.eye));
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 p{(corner & 1) ? box.hi.x : box.lo.x, (corner & 2) ? box.hi.y : box.lo.y,
                   (corner & 4) ? box.hi.z : box.lo.z};
      const Vec3 d = p - cam.eye;
      const float depth = dot(d, f.forward);
      ASSERT_GT(depth, 0.0f);
      EXPECT_LT(std::fabs(dot(d, f.right)) / depth, f.half_width);
      EXPECT_LT(std::fabs(dot(d, f.up)) / depth, f.half_height);
    }
  }
}

TEST(Camera, FramingStandsAtTheBoxsOwnScale) {
  // A scene 1e-18 across is framed from about its own size away, not from a fixed 1e-3 (1e15 of its sizes, where it
  // covers no pixel); a point far from the origin from a distance of order 1e-3 of its distance to the origin.
  const AABB tiny({1e-18f, 1e-18f, 1e-18f}, {2e-18f, 3e-18f, 2e-18f});
  const Camera near = Camera::framing(tiny);
  EXPECT_LT(length(near.eye - near.at), 1e-16f);
  EXPECT_GT(length(near.eye - near.at), 1e-19f);
  const AABB far_point = AABB::of_point({1e6f, 0.0f, 0.0f});
  const Camera far = Camera::framing(far_point);
  EXPECT_GT(length(far.eye - far.at), 100.0f);
  EXPECT_LT(length(far.eye - far.at), 1e4f);
}

TEST(Camera, FramingDegenerateBoxesHasNoNaN) {
  const AABB point = AABB::of_point({2.0f, 3.0f, 4.0f});
  const AABB origin = AABB::of_point({0.0f, 0.0f, 0.0f});
  const AABB subnormal({1e-40f, 0.0f, 0.0f}, {2e-40f, 1e-45f, 0.0f});
  for (const AABB& box : {point, origin, subnormal, AABB::empty()}) {
    const Camera cam = Camera::framing(box);
    EXPECT_TRUE(is_finite(cam.eye));
    EXPECT_TRUE(is_finite(cam.at));
    EXPECT_NE(cam.eye, cam.at);
    EXPECT_TRUE(is_finite(cam.primary_ray(1, 1, 4, 4).direction));
  }
}

TEST(StandardCamera, ParsesTheSharedManifestForBunny) {
  const std::filesystem::path scenes = testing::shared_scenes_dir();
  RAYACCEL_NEED_SHARED_FILE(scenes / "MANIFEST.md");
  const auto cam = standard_camera(scenes / "bunny.ply");
  ASSERT_TRUE(cam.has_value());
  EXPECT_EQ(cam->eye, (Vec3{0.17f, 0.17f, 0.24f}));
  EXPECT_EQ(cam->at, (Vec3{-0.0168f, 0.108f, -0.0015f}));
  EXPECT_EQ(cam->up, (Vec3{0.0f, 1.0f, 0.0f}));
  EXPECT_EQ(cam->fov_degrees, 40.0f);
  EXPECT_FALSE(standard_camera(scenes / "no_such_model.ply").has_value());
}

class StandardCameraFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("rayaccel_camera_test_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  void write_manifest(const std::string& text) { std::ofstream(dir_ / "MANIFEST.md") << text; }
  /// The Error message standard_camera() throws for the model "good", or "" when it does not throw.
  std::string error_for(const std::string& manifest) {
    write_manifest(manifest);
    try {
      standard_camera(dir_ / "good.ply");
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  }
  std::filesystem::path dir_;
};

TEST_F(StandardCameraFile, MalformedLinesNameFileAndLine) {
  const std::string head = "# title\n\n```cameras\ngood eye=1,2,3 at=0,0,0 up=0,1,0 fov=45\n";
  const std::string bad_lines[] = {
      "broken eye=1,2 at=0,0,0 up=0,1,0 fov=45",        // two components
      "broken eye=1,2,x at=0,0,0 up=0,1,0 fov=45",      // not a number
      "broken eye=1,2,3 at=0,0,0 up=0,1,0",             // no fov
      "broken eye=1,2,3 at=0,0,0 up=0,1,0 fov=200",     // fov out of range
      "broken eye=1,2,3 at=0,0,0 up=0,1,0 fov=45 f=2",  // unknown key
      "broken eye=1,2,3 eye=1,2,3 at=0,0,0 up=0,1,0 fov=45",
      "broken eye=1,2,3 at=1,2,3 up=0,1,0 fov=45",  // eye == at
      "broken eye=1,2,3 at=0,0,0 up=0,0,0 fov=45",  // zero up
      "broken eye 1,2,3 at=0,0,0 up=0,1,0 fov=45",
  };
  const std::string manifest_path = (dir_ / "MANIFEST.md").string();
  for (const std::string& bad : bad_lines) {
    const std::string message = error_for(head + bad + "\n```\n");
    EXPECT_NE(message.find(manifest_path + ":5"), std::string::npos) << bad << " -> " << message;
  }
  const std::string unterminated = error_for(head);
  EXPECT_NE(unterminated.find(manifest_path + ":3"), std::string::npos) << unterminated;
}

TEST_F(StandardCameraFile, WellFormedAndMissingCases) {
  write_manifest(
      "```cameras\nother eye=0,0,1 at=0,0,0 up=0,1,0 fov=30\ngood eye=1,2,3 at=0,0,0 up=0,1,0 fov=45\n```\n");
  const auto cam = standard_camera(dir_ / "good.ply");
  ASSERT_TRUE(cam.has_value());
  EXPECT_EQ(cam->eye, (Vec3{1.0f, 2.0f, 3.0f}));
  EXPECT_EQ(cam->fov_degrees, 45.0f);
  EXPECT_FALSE(standard_camera(dir_ / "absent.ply").has_value());
  std::filesystem::remove(dir_ / "MANIFEST.md");
  EXPECT_FALSE(standard_camera(dir_ / "good.ply").has_value());
}

}  // namespace
}  // namespace rayaccel
