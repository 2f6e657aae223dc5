// `rayaccel render SCENE`: a PNG of normals, ambient occlusion or a traversal-cost heat map through any structure
// (the whitted and --cones modes: render_modes.cpp); the default camera is the scene's MANIFEST camera, else one
// framing its bounds.
#include <fmt/core.h>

#include <cmath>
#include <memory>
#include <string>

#include "cli_common.h"
#include "commands.h"
#include "render_modes.h"
#include "rayaccel/generalized/generalized_rays.h"
#include "rayaccel/render/cone_effects.h"
#include "rayaccel/render/renderer.h"

namespace rayaccel::cli {

namespace {

/// Refuses a camera with no view direction or an up along it, saying which values made it: the options given, or
/// the default camera (which a scene too small for float cannot give a position apart from what it looks at).
void check_camera(const Camera& camera, bool eye_given, bool at_given, bool up_given, const Scene& scene) {
  if (length(camera.at - camera.eye) == 0.0f) {
    if (eye_given && at_given) throw UsageError("--eye and --at are the same point");
    if (eye_given || at_given) {
      throw UsageError(std::string(eye_given ? "--eye" : "--at") + " is the point the default camera " +
                       (eye_given ? "looks at" : "stands at") + "; give " + (eye_given ? "--at" : "--eye") + " too");
    }
    const Vec3 extent = scene.bounds().extent();
    throw UsageError(fmt::format("the default camera cannot frame this scene: it is {:g} x {:g} x {:g} across, too "
                                 "small for a camera position apart from its centre in float; give --eye and --at",
                                 extent.x, extent.y, extent.z));
  }
  if (length(cross(camera.at - camera.eye, camera.up)) == 0.0f) {
    throw UsageError(up_given ? "--up is parallel to the view direction"
                              : fmt::format("the default up ({:g},{:g},{:g}) is parallel to the view direction; give "
                                            "--up", camera.up.x, camera.up.y, camera.up.z));
  }
}

int run_render(const RenderArgs& args, bool fov_given, bool threads_given, bool heat_max_given) {
  if (threads_given) require_range(args.threads, 1, 4096, "--threads");
  if (heat_max_given) require_heat_max(args.heat_max);
  const auto [width, height] = parse_resolution(args.resolution, "--res");
  require_range(args.ao_samples, 1, 65536, "--ao-samples");
  if (args.ao_max_samples != 0) require_range(args.ao_max_samples, args.ao_samples, 65536, "--ao-max-samples");
  if (!(args.ao_error >= 0.0f && args.ao_error <= 0.5f)) {
    throw UsageError(fmt::format("--ao-error: {} is not in [0, 0.5]", args.ao_error));
  }
  const bool whitted = args.mode == "whitted";
  ShadingMode mode = ShadingMode::normals;
  WhittedArgs whitted_args;
  if (whitted) {
    whitted_args = parse_whitted_args(args);
    check_reference(args.reference, width, height);
  } else {
    try {
      mode = parse_shading_mode(args.mode);
    } catch (const Error&) {
      throw UsageError("--mode: unknown mode '" + args.mode + "' (known: normals, ao, heatmap, whitted)");
    }
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
  if (!args.cones.empty()) {
    try {
      parse_cone_effect(args.cones);
    } catch (const Error& e) {
      throw UsageError(std::string("--cones: ") + e.what());
    }
    if (whitted || args.beams) throw UsageError("--cones: not with --mode whitted or --beams");
    require_range(args.cone_samples, 1, 65536, "--cone-samples");
    if (args.cone_coverage != "analytic" && args.cone_coverage != "pattern") {
      throw UsageError(fmt::format("--cone-coverage: '{}' is not analytic or pattern", args.cone_coverage));
    }
    require_range(args.cone_rays, 0, 65536, "--cone-rays");
    if (!(args.cone_light_radius > 0.0f && args.cone_light_radius <= 1.0f)) {
      throw UsageError(fmt::format("--cone-light-radius: {} is not in (0, 1]", args.cone_light_radius));
    }
    check_reference(args.reference, width, height);
  }
  check_output_path(args.out, "PNG");
  if (whitted && !args.json.empty()) check_output_path(args.json, "JSON file");
  if (whitted && !args.spp_map.empty()) check_output_path(args.spp_map, "samples-per-pixel PNG");
  const ThreadLimit limit(threads_given ? args.threads : 0);

  Progress progress;
  progress.stage("loading " + args.scene);
  const Scene scene = load_scene_checked(args.scene);
  Camera camera = default_camera(args.scene, scene);
  if (eye) camera.eye = *eye;
  if (at) camera.at = *at;
  if (up) camera.up = *up;
  if (fov_given) camera.fov_degrees = args.fov;
  check_camera(camera, eye.has_value(), at.has_value(), up.has_value(), scene);

  progress.stage("building " + spec);
  auto accel = make_structure(spec, ThreadLimit::active());
  const Stopwatch build_clock;
  accel->build(scene);
  const double build_ms = build_clock.milliseconds();

  if (!args.cones.empty()) {
    render_cone_mode(args, *accel, scene, camera, width, height, progress);
    return 0;
  }
  if (whitted) {
    render_whitted_mode(args, whitted_args, *accel, scene, camera, width, height, build_ms, progress);
    return 0;
  }
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.mode = mode;
  if (heat_max_given) settings.heat_scale = fixed_heat_scale(args.heat_max);
  settings.ao_samples = args.ao_samples;
  settings.ao_max_samples = args.ao_max_samples;
  settings.ao_error = args.ao_error;
  if (args.beams) {
    if (mode == ShadingMode::heatmap) throw UsageError("--beams: not with --mode heatmap (no per-pixel cost)");
    require_range(args.beam_tile, 1, 4096, "--beam-tile");
    require_range(args.beam_min_tile, 1, 4096, "--beam-min-tile");
    if (!generalized::supports_generalized_rays(*accel)) {
      throw UsageError("--beams: structure '" + spec + "' has no beam traversal (use bvh, bvh_wide or kdtree)");
    }
    settings.beams = generalized::BeamOptions{.tile_size = args.beam_tile,
                                              .min_tile = args.beam_min_tile,
                                              .entry_points = !args.beam_root,
                                              .frustum = !args.beam_exact_tests,
                                              .packets = !args.beam_one_by_one};
  }
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
  if (result.beam_stats) {
    const generalized::BeamStats& b = *result.beam_stats;
    const double pixels = static_cast<double>(width) * height;
    fmt::print("beams: {} beams; per pixel {:.3f} beam volume tests, {:.3f} beam/primitive tests, {:.3f} ray node "
               "visits, {:.3f} ray/primitive tests; pixels {:.1f}% missed by beams, {:.1f}% one primitive test, "
               "{:.1f}% on a proven front triangle, {:.1f}% traced from entry points ({:.1f}% in packets, which "
               "take no counts; {:.2f}% of them traced again alone for a possible tie)\n",
               b.beams, b.beam_node_tests / pixels, b.beam_primitive_tests / pixels, b.ray_node_visits / pixels,
               b.ray_primitive_tests / pixels, 100.0 * b.pixels_missed / pixels, 100.0 * b.pixels_one_primitive / pixels,
               100.0 * b.pixels_in_front / pixels, 100.0 * b.pixels_traced / pixels,
               100.0 * b.pixels_in_packets / pixels, 100.0 * b.pixels_retraced / pixels);
  }
  return 0;
}

}  // namespace

Command add_render_command(CLI::App& root) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* app = root.add_subcommand("render", "Render a PNG (normals, ambient occlusion or a heat map)");
  app->add_option("scene", args->scene, "Mesh file or builtin:NAME[:key=value,...]")->required();
  app->add_option("--accel", args->accel,
                  "Structure spec NAME[:key=value,...]; default " + default_accelerator_spec());
  app->add_option("--eye", args->eye,
                  "Camera position x,y,z (default: for a mesh file, its camera in the ```cameras block of a "
                  "MANIFEST.md beside it, which render reads when present; else one framing the scene)");
  app->add_option("--at", args->at, "Point looked at x,y,z");
  app->add_option("--up", args->up, "Up hint x,y,z");
  CLI::Option* fov = app->add_option("--fov", args->fov, "Full vertical field of view in degrees");
  app->add_option("--res", args->resolution, "Image size WxH")->capture_default_str();
  app->add_option("--mode", args->mode, "normals, ao, heatmap or whitted (recursive: mirrors, glass, shadows)")
      ->capture_default_str();
  app->add_option("--ao-samples", args->ao_samples, "ao: shadow rays per hit (the first round when adaptive)")
      ->capture_default_str();
  app->add_option("--ao-max-samples", args->ao_max_samples,
                  "ao: adaptive sampling, further rounds of --ao-samples rays where the estimate is uncertain, up to "
                  "this many per hit (0: off)")
      ->capture_default_str();
  app->add_option("--ao-error", args->ao_error, "ao: adaptive sampling stops at this standard error")
      ->capture_default_str();
  app->add_option("--max-depth", args->max_depth, "whitted: secondary rays per path at most")->capture_default_str();
  app->add_option("--min-weight", args->min_weight,
                  "whitted: a reflection or refraction ray whose weight in the pixel is below this is not traced "
                  "(adaptive tree depth, Hall & Greenberg 1983; 0 = fixed depth)")
      ->capture_default_str();
  app->add_option("--aa", args->aa,
                  "whitted: uniform:n=N (N x N sub-squares per pixel, corners shared) or "
                  "adaptive:threshold=T,max_level=L (subdivide where the corners' contrast >= T)")
      ->capture_default_str();
  app->add_option("--shadows", args->shadows, "whitted: any (any-hit shadow rays) or closest")->capture_default_str();
  app->add_option("--mirror", args->mirror, "whitted: mirror weight of a mesh file's surfaces, 0 to 1")
      ->capture_default_str();
  app->add_option("--light-samples", args->light_samples, "whitted: shadow rays per spherical light")
      ->capture_default_str();
  app->add_option("--light-radius", args->light_radius,
                  "whitted: the light's radius as a fraction of the scene diagonal (0: a point light, no noise)")
      ->capture_default_str();
  app->add_option("--reference", args->reference,
                  "whitted, --cones: a PNG to measure the image's error (RMSE, PSNR) against");
  app->add_option("--json", args->json, "whitted: write the rays traced by kind and the timings to this JSON file");
  app->add_option("--spp-map", args->spp_map, "whitted: write a heat map of samples per pixel to this PNG");
  app->add_flag("--beams", args->beams,
               "normals/ao: primary visibility by beams over bvh, bvh_wide or kdtree (the same hits as single rays)");
  app->add_option("--beam-tile", args->beam_tile, "--beams: side of the first beams in pixels")->capture_default_str();
  app->add_option("--beam-min-tile", args->beam_min_tile, "--beams: beams are not split below this side in pixels")
      ->capture_default_str();
  app->add_flag("--beam-exact-tests", args->beam_exact_tests,
               "--beams: the double-precision beam/box and beam/triangle tests instead of the float frustum (for "
               "comparison)");
  app->add_flag("--beam-one-by-one", args->beam_one_by_one,
               "--beams over bvh_wide: trace the undecided rays one by one, with node and primitive counts, instead "
               "of in 4 x 2 packets");
  app->add_flag("--beam-root", args->beam_root,
               "--beams: trace the undecided rays from the root instead of the tile's entry point (for comparison)");
  app->add_option("--cones", args->cones,
                  "shadows (soft shadows from a spherical light) or aa (one cone per pixel), by cone queries over bvh, "
                  "bvh_wide or kdtree; with --cone-rays N the same estimate by N random rays per cone instead");
  app->add_option("--cone-samples", args->cone_samples, "--cones with --cone-coverage pattern: directions per cone")
      ->capture_default_str();
  app->add_option("--cone-coverage", args->cone_coverage,
                  "--cones: analytic (exact solid angle per triangle, added front to back; Amanatides 1984) or "
                  "pattern (closest hits of --cone-samples rays)")
      ->capture_default_str();
  app->add_option("--cone-rays", args->cone_rays, "--cones: random rays per cone instead of the cone query (0: cones)")
      ->capture_default_str();
  app->add_option("--cone-light-radius", args->cone_light_radius,
                  "--cones shadows: the light's radius over the scene diagonal")
      ->capture_default_str();
  app->add_option("--out", args->out, "Output PNG file")->capture_default_str();
  CLI::Option* threads = app->add_option("--threads", args->threads, "Worker threads (>= 1)");
  CLI::Option* heat_max = app->add_option("--heat-max", args->heat_max, kHeatMaxHelp);
  return {app, [args, fov, threads, heat_max] {
            return run_render(*args, fov->count() > 0, threads->count() > 0, heat_max->count() > 0);
          }};
}

}  // namespace rayaccel::cli
