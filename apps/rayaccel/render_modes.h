// Internal to the CLI: what `rayaccel render` takes from the command line (render_command.cpp) and its two
// modes beyond the shading modes, whitted and --cones (render_modes.cpp).
#pragma once

#include <cstdint>
#include <string>

#include "rayaccel/render/camera.h"
#include "rayaccel/render/whitted.h"

namespace rayaccel {
class Accelerator;
class Scene;
}  // namespace rayaccel

namespace rayaccel::cli {

class Progress;

/// What the command line asks of `rayaccel render` (plain fields, as BenchArgs in bench.h holds the bench's).
struct RenderArgs {
  std::string scene;
  std::string accel;
  std::string eye, at, up;
  float fov = 0.0f;
  std::string resolution = "512x512";
  std::string mode = "normals";
  std::string out = "render.png";
  int threads = 0;
  std::uint64_t heat_max = 0;
  // ao mode
  int ao_samples = 8;
  int ao_max_samples = 0;
  float ao_error = 0.05f;
  // whitted mode
  int max_depth = 5;
  float min_weight = 0.0f;
  std::string aa = "uniform:n=1";
  std::string shadows = "any";
  float mirror = 0.0f;
  int light_samples = 4;
  float light_radius = 0.02f;
  std::string reference;
  std::string json;
  std::string spp_map;
  // normals and ao modes: primary visibility by beams
  bool beams = false;
  int beam_tile = 8;
  bool beam_root = false;
  int beam_min_tile = 8;
  bool beam_exact_tests = false;
  bool beam_one_by_one = false;
  // cone effects
  std::string cones;
  int cone_samples = 64;
  std::string cone_coverage = "analytic";
  int cone_rays = 0;
  float cone_light_radius = 0.05f;
};

/// The whitted mode's settings, checked before any work.
struct WhittedArgs {
  WhittedSettings settings;
  AntiAliasing aa;
  MaterialOptions materials;
};
/// The whitted mode's settings from the command line; UsageError naming the option at fault.
WhittedArgs parse_whitted_args(const RenderArgs& args);

/// Renders --mode whitted and prints (and writes with --json) the rays traced by kind.
void render_whitted_mode(const RenderArgs& args, const WhittedArgs& w, const Accelerator& accel, const Scene& scene,
                         const Camera& camera, int width, int height, double build_ms, Progress& progress);

/// Renders --cones shadows|aa (or with --cone-rays its many-ray estimate) and prints its cost and error.
void render_cone_mode(const RenderArgs& args, const Accelerator& accel, const Scene& scene, const Camera& camera,
                      int width, int height, Progress& progress);

/// A bad --reference (unreadable, or not the size of the image) fails before the work.
void check_reference(const std::string& reference, int width, int height);

}  // namespace rayaccel::cli
