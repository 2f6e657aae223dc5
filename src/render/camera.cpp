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

Ray CameraFrame::ray_at(float x, float y) const {
  const float sx = (2.0f * x / static_cast<float>(width) - 1.0f) * half_width;
  const float sy = (1.0f - 2.0f * y / static_cast<float>(height)) * half_height;
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
  // The box's own size sets the distance, so a scene 1e-18 across is framed from about 1e-18 away (an absolute
  // floor would put it at a speck of a pixel, and its rays in the far-ray regime). A flat or single-point box still
  // needs a distance resolvable at the magnitude of its coordinates, kept out of float's subnormal range; a point at
  // the origin gets 1e-3.
  const double size =
      std::fmax(0.5 * std::sqrt(ex * ex + ey * ey + ez * ez), max_component(abs(center)) * 1e-3);
  const double radius = size > 0.0 ? std::fmax(size, 1e-30) : 1e-3;

  Camera cam;
  cam.fov_degrees = kDefaultFramingFov;
  cam.at = center;
  cam.up = {0.0f, 1.0f, 0.0f};
  const Vec3 view = normalize(Vec3{0.55f, 0.4f, 1.0f});  // from the front right, a little above
  const Vec3 right = normalize(cross(-view, cam.up));
  const Vec3 image_up = cross(right, -view);
  // The nearest eye distance at which every box corner projects inside 90% of the (square) image: a corner at
  // offset p from the center lies at depth distance - dot(p, view) and needs |lateral offset| / depth <= limit.
  const double limit = 0.9 * std::tan(kDefaultFramingFov * std::numbers::pi / 360.0);
  double distance = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 c{(corner & 1) ? box.hi.x : box.lo.x, (corner & 2) ? box.hi.y : box.lo.y,
                 (corner & 4) ? box.hi.z : box.lo.z};
    const Vec3 p = c - center;
    const double lateral = std::fmax(std::fabs(dot(p, right)), std::fabs(dot(p, image_up)));
    distance = std::fmax(distance, dot(p, view) + std::fmax(lateral / limit, 0.5 * radius));
  }
  cam.eye = {static_cast<float>(center.x + view.x * distance), static_cast<float>(center.y + view.y * distance),
             static_cast<float>(center.z + view.z * distance)};
  if (!is_finite(cam.eye)) return Camera{};  // a box near the float range: no finite eye frames it
  return cam;
}

}  // namespace rayaccel
