// Pinhole camera: eye, look-at point, up hint, full vertical field of view. Image x points along
// normalize(cross(forward, up)), image y along the orthogonalized up (the convention of shared/scenes/MANIFEST.md).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "rayaccel/core/aabb.h"
#include "rayaccel/core/ray.h"

namespace rayaccel {

/// The orthonormal frame of a camera for one image size, computed once and then used per pixel.
struct CameraFrame {
  Vec3 eye;
  Vec3 forward;           ///< unit, from eye toward the look-at point
  Vec3 right;             ///< unit, normalize(cross(forward, up)): image x
  Vec3 up;                ///< unit, cross(right, forward): image y (toward row 0)
  float half_height = 0;  ///< tan(fov / 2): image-plane half height at distance 1
  float half_width = 0;   ///< half_height * width / height
  int width = 0;
  int height = 0;

  /// Ray through the center of pixel (x, y); row 0 is the top row. Unit direction, t in [0, +inf).
  Ray ray(int x, int y) const;
  /// Ray through the image-plane point (x, y) in pixels: (0, 0) the top-left corner of the image, (width, height)
  /// the bottom-right; pixel (i, j)'s center is (i + 0.5, j + 0.5). Unit direction, t in [0, +inf).
  Ray ray_at(float x, float y) const;
};

struct Camera {
  Vec3 eye{0.0f, 0.0f, 1.0f};
  Vec3 at{0.0f, 0.0f, 0.0f};
  Vec3 up{0.0f, 1.0f, 0.0f};
  float fov_degrees = 45.0f;

  /// The frame for a width x height image (both > 0, else Error). Degenerate cameras never give NaN: eye == at
  /// looks along -z, and an up hint parallel to the view direction is replaced by the world axis least aligned
  /// with it; a fov outside (0, 180) degrees is clamped into it.
  CameraFrame frame(int width, int height) const;
  /// Ray through the center of pixel (x, y) of a width x height image; row 0 is the top row. Unit direction.
  /// (Builds the frame per call; use frame() for many rays.)
  Ray primary_ray(int x, int y, int width, int height) const;
  /// A camera that frames the whole box from a three-quarter view (front right, slightly above; Y up, 40 degree
  /// fov), as close as it can with every box corner inside the central 90% of a square image. Flat or
  /// single-point boxes get a finite nonzero distance; an empty or non-finite box gives the default camera.
  static Camera framing(const AABB& box);
};

/// The standard camera of a shared scene file: reads MANIFEST.md beside the file and returns the line of its
/// ```cameras block named after the file stem ("NAME eye=x,y,z at=x,y,z up=x,y,z fov=DEG"). Returns nullopt when
/// there is no manifest, no cameras block, or no line for this stem. Every line of the block is checked: a
/// malformed one (missing, repeated or unknown key, bad number, fov outside (0, 180), eye == at, zero up) or an
/// unterminated block throws Error naming the manifest and the line number.
std::optional<Camera> standard_camera(const std::filesystem::path& scene_file);

}  // namespace rayaccel
