// Pinhole camera: the per-image frame, primary rays through pixel centers, and automatic framing of a box.
#include "rayaccel/render/camera.h"

#include <cmath>
#include <numbers>
#include <string>

#include "rayaccel/core/error.h"

namespace rayaccel {

namespace {

constexpr float kDefaultFramingFov = 40.0f;

/// The world axis least aligned with v: never parallel to a nonzero v.
Vec3 least_aligned_axis(const Vec3& v) {
  const Vec3 a = abs(v);
  if (a.x <= a.y && a.x <= a.z) return {1.0f, 0.0f, 0.0f};
  if (a.y <= a.z) return {0.0f, 1.0f, 0.0f};
  return {0.0f, 0.0f, 1.0f};
}

}  // namespace

CameraFrame Camera::frame(int width, int height) const {
  if (width <= 0 || height <= 0) {
    throw Error("camera: image size " + std::to_string(width) + "x" + std::to_string(height) + " is not positive");
  }
  CameraFrame f;
  f.eye = eye;
  f.width = width;
  f.height = height;
  f.forward = normalize(at - eye);
  if (!is_finite(f.forward) || f.forward == Vec3{}) f.forward = {0.0f, 0.0f, -1.0f};
  f.right = normalize(cross(f.forward, up));
  if (!is_finite(f.right) || f.right == Vec3{}) f.right = normalize(cross(f.forward, least_aligned_axis(f.forward)));
  f.up = cross(f.right, f.forward);
  float fov = std::isfinite(fov_degrees) ? fov_degrees : 45.0f;
  fov = std::fmin(std::fmax(fov, 1e-3f), 179.0f);
  f.half_height = std::tan(fov * std::numbers::pi_v<float> / 360.0f);
  f.half_width = f.half_height * static_cast<float>(width) / static_cast<float>(height);
  return f;
}

Ray CameraFrame::ray(int x, int y) const {
  // Pixel centers map to [-1, 1] across the image; row 0 (the top) is +up.
  const float sx = (2.0f * (static_cast<float>(x) + 0.5f) / static_cast<float>(width) - 1.0f) * half_width;
  const float sy = (1.0f - 2.0f * (static_cast<float>(y) + 0.5f) / static_cast<float>(height)) * half_height;
  Ray r;
  r.origin = eye;
  r.direction = normalize(forward + right * sx + up * sy);
  return r;
}

Ray Camera::primary_ray(int x, int y, int width, int height) const { return frame(width, height).ray(x, y); }

Camera Camera::framing(const AABB& box) {
  if (box.is_empty() || !box.is_finite()) return Camera{};
  // Work in double so huge boxes (1e30) neither overflow the diagonal nor lose the center.
  const double ex = double(box.hi.x) - box.lo.x, ey = double(box.hi.y) - box.lo.y, ez = double(box.hi.z) - box.lo.z;
  const Vec3 center{static_cast<float>(0.5 * (double(box.lo.x) + box.hi.x)),
                    static_cast<float>(0.5 * (double(box.lo.y) + box.hi.y)),
                    static_cast<float>(0.5 * (double(box.lo.z) + box.hi.z))};
  double radius = 0.5 * std::sqrt(ex * ex + ey * ey + ez * ez);
  // A single point: pick a small distance relative to its coordinates so the eye differs from it in float.
  const double magnitude = max_component(abs(center));
  radius = std::fmax(radius, std::fmax(magnitude * 1e-3, 1e-3));

  Camera cam;
  cam.fov_degrees = kDefaultFramingFov;
  cam.at = center;
  cam.up = {0.0f, 1.0f, 0.0f};
  const double half_fov = kDefaultFramingFov * std::numbers::pi / 360.0;
  const double distance = 1.1 * radius / std::sin(half_fov);  // the bounding sphere fits with a 10% margin
  const Vec3 view = normalize(Vec3{0.55f, 0.4f, 1.0f});  // from the front right, a little above
  cam.eye = {static_cast<float>(center.x + view.x * distance), static_cast<float>(center.y + view.y * distance),
             static_cast<float>(center.z + view.z * distance)};
  return cam;
}

}  // namespace rayaccel
