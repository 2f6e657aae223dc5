// Pinhole camera: eye, look-at point, up hint, full vertical field of view. Image x points along
// normalize(cross(forward, up)), image y along the orthogonalized up (the convention of shared/scenes/MANIFEST.md).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/ray.h"

namespace rayaccel {

struct Camera {
  Vec3 eye{0.0f, 0.0f, 1.0f};
  Vec3 at{0.0f, 0.0f, 0.0f};
  Vec3 up{0.0f, 1.0f, 0.0f};
  float fov_degrees = 45.0f;

  /// Ray through the center of pixel (x, y) of a width x height image; row 0 is the top row. Unit direction.
  Ray primary_ray(int x, int y, int width, int height) const;
  /// A camera that frames the whole box from a three-quarter view.
  static Camera framing(const AABB& box);
};

/// The standard camera of a shared scene file: looks for MANIFEST.md beside the file and its ```cameras block.
std::optional<Camera> standard_camera(const std::filesystem::path& scene_file);

}  // namespace rayaccel
