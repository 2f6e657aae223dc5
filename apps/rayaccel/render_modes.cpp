// The whitted and --cones modes of `rayaccel render` (render_modes.h): each renders, writes its PNG (and whitted
// its JSON report and samples-per-pixel map) as one batch of outputs, and prints its cost and error.
#include "render_modes.h"

#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

#include "cli_common.h"
#include "rayaccel/core/output_batch.h"
#include "rayaccel/generalized/generalized_rays.h"
#include "rayaccel/render/cone_effects.h"
#include "rayaccel/render/image_compare.h"

namespace rayaccel::cli {

WhittedArgs parse_whitted_args(const RenderArgs& args) {
  WhittedArgs w;
  w.settings.max_depth = args.max_depth;
  w.settings.min_weight = args.min_weight;
  if (args.shadows != "any" && args.shadows != "closest") {
    throw UsageError("--shadows: '" + args.shadows + "' is not any or closest");
  }
  w.settings.any_hit_shadows = args.shadows == "any";
  w.materials.mirror = args.mirror;
  require_range(args.light_samples, 1, 4096, "--light-samples");
  if (!(args.light_radius >= 0.0f && args.light_radius <= 1.0f)) {
    throw UsageError(fmt::format("--light-radius: {} is not in [0, 1]", args.light_radius));
  }
  if (!(args.mirror >= 0.0f && args.mirror <= 1.0f)) {
    throw UsageError(fmt::format("--mirror: {} is not in [0, 1]", args.mirror));
  }
  try {
    check_settings(w.settings);
    w.aa = parse_anti_aliasing(args.aa);
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
  return w;
}

/// Renders --mode whitted and prints (and writes with --json) the rays traced by kind.
void render_whitted_mode(const RenderArgs& args, const WhittedArgs& w, const Accelerator& accel, const Scene& scene,
                         const Camera& camera, int width, int height, double build_ms, Progress& progress) {
  const SceneMaterials materials = default_materials(scene, w.materials);
  const std::vector<Light> lights = default_lights(scene.bounds(), camera, args.light_samples, args.light_radius);
  WhittedSettings settings = w.settings;
  settings.up = camera.up;
  progress.stage(fmt::format("rendering {}x{} whitted, --aa {}", width, height, args.aa));
  const WhittedResult result = render_whitted(accel, scene, camera, width, height, materials, lights, settings, w.aa,
                                              [&progress](float f) { progress.update(f); });
  progress.done();
  const RayCounts& c = result.counts;
  const double pixels = static_cast<double>(width) * height;
  nlohmann::json report = {{"scene", scene.name()},
                           {"accel", accel.spec()},
                           {"width", width},
                           {"height", height},
                           {"aa", args.aa},
                           {"max_depth", settings.max_depth},
                           {"min_weight", settings.min_weight},
                           {"shadows", args.shadows},
                           {"build_ms", build_ms},
                           {"render_ms", result.milliseconds},
                           {"camera_rays", c.camera},
                           {"shadow_rays", c.shadow},
                           {"reflection_rays", c.reflection},
                           {"refraction_rays", c.refraction},
                           {"rays", c.total()},
                           {"rays_per_pixel", static_cast<double>(c.total()) / pixels},
                           {"samples_per_pixel", static_cast<double>(result.samples.sample_count) / pixels},
                           {"nodes_visited", c.nodes_visited},
                           {"primitives_tested", c.primitives_tested}};
  std::string error_text;
  if (!args.reference.empty()) {
    const ImageError e = compare_images(result.image, load_png(args.reference));
    report["rmse"] = e.rmse;
    report["psnr_db"] = std::isinf(e.psnr) ? nlohmann::json("inf") : nlohmann::json(e.psnr);
    error_text = fmt::format(", RMSE {:.3f}, PSNR {:.2f} dB against {}", e.rmse, e.psnr, args.reference);
  }
  // Every output written, then committed together: a failure of any leaves all of them as they were.
  OutputBatch outputs;
  result.image.save_png(outputs.stage(args.out));
  if (!args.spp_map.empty()) samples_per_pixel_image(result.samples).save_png(outputs.stage(args.spp_map));
  if (!args.json.empty()) write_file_atomically(outputs.stage(args.json), report.dump(2) + "\n", "JSON file");
  outputs.commit();
  fmt::print("wrote {} ({}x{}, whitted, {}): build {:.2f} ms, render {:.2f} ms; rays: {} camera, {} shadow, {} "
             "reflection, {} refraction ({:.2f} per pixel); {} nodes visited, {} primitive tests{}\n",
             args.out, width, height, accel.spec(), build_ms, result.milliseconds, c.camera, c.shadow, c.reflection,
             c.refraction, static_cast<double>(c.total()) / pixels, c.nodes_visited, c.primitives_tested, error_text);
}

/// Renders --cones shadows|aa (or with --cone-rays its many-ray estimate) and prints its cost and error.
void render_cone_mode(const RenderArgs& args, const Accelerator& accel, const Scene& scene, const Camera& camera,
                      int width, int height, Progress& progress) {
  ConeEffectSettings settings;
  settings.width = width;
  settings.height = height;
  settings.effect = parse_cone_effect(args.cones);
  settings.cone_samples = args.cone_samples;
  settings.coverage = args.cone_coverage == "pattern" ? generalized::ConeCoverage::pattern
                                                      : generalized::ConeCoverage::analytic;
  settings.rays = args.cone_rays;
  settings.light_radius_fraction = args.cone_light_radius;
  progress.stage(fmt::format("rendering {}x{} cone {}", width, height, args.cones));
  const ConeEffectResult result = render_cone_effect(accel, scene, camera, settings);
  progress.done();
  const double pixels = static_cast<double>(width) * height;
  std::string error_text;
  if (!args.reference.empty()) {
    const ImageError e = compare_images(result.image, load_png(args.reference));
    error_text = fmt::format(", RMSE {:.3f}, PSNR {:.2f} dB against {}", e.rmse, e.psnr, args.reference);
  }
  OutputBatch outputs;
  result.image.save_png(outputs.stage(args.out));
  outputs.commit();
  fmt::print("wrote {} ({}x{}, cones {}, {}): {} {} in {:.2f} ms; per pixel {:.2f} node visits, {:.2f} primitive "
             "tests{}\n",
             args.out, width, height, args.cones,
             args.cone_rays > 0 ? fmt::format("{} rays per cone", args.cone_rays)
                : settings.coverage == generalized::ConeCoverage::pattern
                    ? fmt::format("{} pattern directions per cone", args.cone_samples)
                    : std::string("analytic coverage"),
             result.queries, args.cone_rays > 0 ? "rays traced" : "cones queried", result.milliseconds,
             static_cast<double>(result.cost.nodes_visited) / pixels,
             static_cast<double>(result.cost.primitives_tested) / pixels, error_text);
}

/// A bad --reference (unreadable, or not the size of the image) fails before the work.
void check_reference(const std::string& reference, int width, int height) {
  if (reference.empty()) return;
  const Image image = load_png(reference);
  if (image.width != width || image.height != height) {
    throw UsageError(fmt::format("--reference: {} is {}x{}, but the image is {}x{} (--res)", reference, image.width,
                                 image.height, width, height));
  }
}

}  // namespace rayaccel::cli
