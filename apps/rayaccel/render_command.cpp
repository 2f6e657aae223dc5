// `rayaccel render SCENE`: renders normals, ambient occlusion or a traversal-cost heat map through any structure
// and writes a PNG. The default camera is the scene's MANIFEST camera, else one framing the scene's bounds.
#include <fmt/core.h>

#include <cmath>
#include <memory>
#include <string>

#include "cli_common.h"
#include "commands.h"
#include "rayaccel/render/renderer.h"

namespace rayaccel::cli {

namespace {

struct RenderArgs {
  std::string scene;
  std::string accel;
  std::string eye, at, up;
  float fov = 0.0f;
  std::string resolution = "512x512";
  std::string mode = "normals";
  std::string out = "render.png";
  int threads = 0;
};

int run_render(const RenderArgs& args, bool fov_given, bool threads_given) {
  if (threads_given) require_range(args.threads, 1, 4096, "--threads");
  const auto [width, height] = parse_resolution(args.resolution, "--res");
  ShadingMode mode;
  try {
    mode = parse_shading_mode(args.mode);
  } catch (const Error& e) {
    throw UsageError(std::string("--mode: ") + e.what());
  }
  // Parse every camera value before loading anything, so a typo fails fast.
  const auto eye = args.eye.empty() ? std::optional<Vec3>() : parse_vec3(args.eye, "--eye");
  const auto at = args.at.empty() ? std::optional<Vec3>() : parse_vec3(args.at, "--at");
  const auto up = args.up.empty() ? std::optional<Vec3>() : parse_vec3(args.up, "--up");
  if (fov_given && !(args.fov > 0.0f && args.fov < 180.0f)) {
    throw UsageError(fmt::format("--fov: {} is not an angle in (0, 180) degrees", args.fov));
  }
  const std::string spec = args.accel.empty() ? default_accelerator_spec() : args.accel;
  check_accelerator_spec(spec);
  check_output_path(args.out, "PNG");
  const ThreadLimit limit(threads_given ? args.threads : 0);

  Progress progress;
  progress.stage("loading " + args.scene);
  const Scene scene = load_scene_checked(args.scene);
  Camera camera = default_camera(args.scene, scene);
  if (eye) camera.eye = *eye;
  if (at) camera.at = *at;
  if (up) camera.up = *up;
  if (fov_given) camera.fov_degrees = args.fov;
  if (length(camera.at - camera.eye) == 0.0f) throw UsageError("--eye and --at are the same point");
  if (length(cross(camera.at - camera.eye, camera.up)) == 0.0f) throw UsageError("--up is parallel to the view direction");

  progress.stage("building " + spec);
  auto accel = make_structure(spec, ThreadLimit::active());
  const Stopwatch build_clock;
  accel->build(scene);
  const double build_ms = build_clock.milliseconds();

  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.mode = mode;
  progress.stage(fmt::format("rendering {}x{} {}", width, height, args.mode));
  settings.progress = [&progress](float fraction) { progress.update(fraction); };
  const RenderResult result = render(*accel, scene, camera, settings);
  result.image.save_png(args.out);
  progress.done();
  const double rays = static_cast<double>(std::max<std::uint64_t>(result.rays, 1));
  fmt::print("wrote {} ({}x{}, {}, {}): build {:.2f} ms, trace {:.2f} ms, {} rays, {:.2f} nodes/ray, "
             "{:.2f} primitive tests/ray\n",
             args.out, width, height, args.mode, accel->spec(), build_ms, result.trace_milliseconds, result.rays,
             static_cast<double>(result.total.nodes_visited) / rays,
             static_cast<double>(result.total.primitives_tested) / rays);
  return 0;
}

}  // namespace

Command add_render_command(CLI::App& root) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* app = root.add_subcommand("render", "Render a PNG (normals, ambient occlusion or a heat map)");
  app->add_option("scene", args->scene, "Mesh file or builtin:NAME[:key=value,...]")->required();
  app->add_option("--accel", args->accel, "Structure spec NAME[:key=value,...]; default bvh");
  app->add_option("--eye", args->eye, "Camera position x,y,z (default: the scene's standard camera)");
  app->add_option("--at", args->at, "Point looked at x,y,z");
  app->add_option("--up", args->up, "Up hint x,y,z");
  CLI::Option* fov = app->add_option("--fov", args->fov, "Full vertical field of view in degrees");
  app->add_option("--res", args->resolution, "Image size WxH")->capture_default_str();
  app->add_option("--mode", args->mode, "normals, ao or heatmap")->capture_default_str();
  app->add_option("--out", args->out, "Output PNG file")->capture_default_str();
  CLI::Option* threads = app->add_option("--threads", args->threads, "Worker threads (>= 1)");
  return {app, [args, fov, threads] { return run_render(*args, fov->count() > 0, threads->count() > 0); }};
}

}  // namespace rayaccel::cli
