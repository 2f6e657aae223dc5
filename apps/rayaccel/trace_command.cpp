// `rayaccel trace SCENE RAYS`: build (median of three) or --load, trace a .rays file R times (median), --save, write
// .hits or .occ and one JSON summary line (--skip / --mask: companion .ids files, a query context); --precision double
// and --instances hand over to their own files.
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "cli_common.h"
#include "commands.h"
#include "trace_double.h"
#include "trace_passes.h"
#include "trace_instanced.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "rayaccel/core/output_batch.h"
#include "rayaccel/core/query_context.h"
#include "rayaccel/scene/ray_io.h"

namespace rayaccel::cli {

namespace {

struct TraceArgs {
  std::string scene;
  std::string rays;
  std::string accel;
  bool occlusion = false;
  bool packets = false;
  int threads = 0;
  int repeat = 5;
  std::string out;
  std::string save;  ///< write the built structure here (Accelerator::save())
  std::string load;  ///< load the structure from here instead of building (load_accelerator())
  std::string precision = "float";  ///< "double": trace_double.cpp
  std::string offset;               ///< --offset (double only)
  bool instances = false;               ///< the two-level trace (trace_instanced.h)
  std::vector<std::string> geometries;  ///< --geometry, with --instances only
  std::string top;                      ///< --top, with --instances only
  std::string skip;                     ///< --skip: .ids file, a primitive per ray to ignore
  std::string mask;                     ///< --mask: .ids file, a ray mask per ray
  std::string geometry_mask;            ///< --geometry-mask: M or M,M,...: every geometry's mask, or one each
  std::string skip_geometry;            ///< --skip-geometry: .ids file, a geometry per ray to ignore
  std::string geometry_ids;             ///< --geometry-ids: .ids file, each hit's geometry (companion of --out)
  std::string enabled;                  ///< --enabled: .ids file, per primitive, 0 hides it
};

/// The masks of --geometry-mask, one per geometry of the scene: "M" gives every geometry M, "M0,M1,..." one each
/// (decimal or 0x hex, uint32). UsageError naming the value, or both counts, otherwise.
std::vector<std::uint32_t> parse_geometry_masks(const std::string& text, std::uint32_t geometries) {
  std::vector<std::uint32_t> masks;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    std::size_t used = 0;
    unsigned long long value = 0;
    try {
      value = item.empty() || item[0] == '-' ? ~0ull : std::stoull(item, &used, 0);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || value > 0xFFFFFFFFull) {
      throw UsageError("--geometry-mask: '" + item + "' is not a uint32 (decimal or 0x hex)");
    }
    masks.push_back(static_cast<std::uint32_t>(value));
    start = comma + 1;
  }
  if (masks.size() == 1) return std::vector<std::uint32_t>(geometries, masks[0]);
  if (masks.size() != geometries) {
    throw UsageError("--geometry-mask: " + std::to_string(masks.size()) + " masks for a scene of " +
                     std::to_string(geometries) + " geometries (give one mask for all, or one per geometry)");
  }
  return masks;
}

/// Reads a companion .ids file of --skip or --mask (one uint32 per ray); Error naming the file and both counts when
/// it does not match the rays.
std::vector<std::uint32_t> read_companion(const std::string& path, std::size_t rays, const char* option) {
  std::vector<std::uint32_t> ids = read_ids(path);
  if (ids.size() != rays) {
    throw Error(std::string(option) + " '" + path + "': " + std::to_string(ids.size()) + " entries for " +
                std::to_string(rays) + " rays (one uint32 per ray)");
  }
  return ids;
}

/// --precision double: refuses the options the double path lacks, then runs it.
int run_trace_double_checked(const TraceArgs& args) {
  for (const auto& [given, name] : {std::pair{args.packets, "--packets"}, std::pair{!args.save.empty(), "--save"},
                                    std::pair{!args.load.empty(), "--load"}}) {
    if (given) throw UsageError(std::string(name) + " is not available with --precision double");
  }
  return run_trace_double({.scene = args.scene, .rays = args.rays, .accel = args.accel, .offset = args.offset,
                           .out = args.out, .occlusion = args.occlusion, .repeat = args.repeat});
}

int run_trace_instanced_hook(const TraceArgs& args, bool threads_given) {
  if (args.packets) throw UsageError("--packets cannot be combined with --instances");
  if (!args.save.empty() || !args.load.empty()) {
    throw UsageError("--save and --load cannot be combined with --instances");
  }
  return run_trace_instanced({args.scene, args.geometries, args.rays, args.accel, args.occlusion, args.threads,
                              args.repeat, args.out, args.top},
                             threads_given);
}

int run_trace(const TraceArgs& args, bool threads_given) {
  if (args.instances && args.precision == "double") {
    throw UsageError("--instances traces in float; it cannot be combined with --precision double");
  }
  const bool with_context = !args.skip.empty() || !args.mask.empty() || !args.geometry_mask.empty() ||
                            !args.skip_geometry.empty() || !args.enabled.empty();
  if ((with_context || !args.geometry_ids.empty()) && (args.instances || args.precision == "double")) {
    throw UsageError("--skip, --skip-geometry, --mask, --geometry-mask, --enabled and --geometry-ids work without "
                     "--instances and --precision double");
  }
  if (!args.geometry_ids.empty() && (args.occlusion || args.out.empty())) {
    throw UsageError("--geometry-ids writes the companion of the --out .hits file: it needs --out, not --occlusion");
  }
  if (args.instances) return run_trace_instanced_hook(args, threads_given);
  if (!args.geometries.empty()) throw UsageError("--geometry needs --instances");
  if (!args.top.empty()) throw UsageError("--top needs --instances");
  if (threads_given) require_range(args.threads, 1, 4096, "--threads");
  require_range(args.repeat, 1, 1000000, "--repeat");
  if (args.precision == "double") {
    const ThreadLimit limit(threads_given ? args.threads : 0);
    return run_trace_double_checked(args);
  }
  if (!args.offset.empty()) throw UsageError("--offset places the scene in double; it needs --precision double");
  if (!args.load.empty() && !args.accel.empty()) {
    throw UsageError("--load takes the structure from the file; leave out --accel");
  }
  const std::string spec = args.accel.empty() ? default_accelerator_spec() : args.accel;
  check_accelerator_spec(spec);
  if (!args.out.empty()) check_output_path(args.out, args.occlusion ? "occlusion file" : "hit file");
  if (!args.geometry_ids.empty()) check_output_path(args.geometry_ids, "geometry id file");
  if (!args.save.empty()) {
    if (args.load.empty() && !make_accelerator(spec)->supports_save()) {
      throw UsageError("--save: '" + spec + "' cannot be saved (saved structures: bvh, every volume, and bvh_wide)");
    }
    check_output_path(args.save, "saved structure");
  }
  const ThreadLimit limit(threads_given ? args.threads : 0);

  GeometryTable geometries;  // the scene file's meshes, in import_mesh()'s order
  const Scene scene = load_scene_checked(args.scene, &geometries);
  const std::vector<Ray> rays = read_rays(args.rays);
  // The query context of --skip, --skip-geometry, --mask and --geometry-mask (off when none is given).
  std::vector<std::uint32_t> skip, skip_geometry, mask, geometry_masks;
  if (!args.skip.empty()) skip = read_companion(args.skip, rays.size(), "--skip");
  if (!args.skip_geometry.empty()) skip_geometry = read_companion(args.skip_geometry, rays.size(), "--skip-geometry");
  if (!args.mask.empty()) mask = read_companion(args.mask, rays.size(), "--mask");
  if (!args.geometry_mask.empty()) {
    geometry_masks = parse_geometry_masks(args.geometry_mask, geometries.geometry_count());
  }
  std::vector<std::uint8_t> enabled;
  if (!args.enabled.empty()) {
    const std::vector<std::uint32_t> switches = read_ids(args.enabled);
    if (switches.size() != scene.primitive_count()) {
      throw Error("--enabled '" + args.enabled + "': " + std::to_string(switches.size()) + " entries for " +
                  std::to_string(scene.primitive_count()) + " primitives (one uint32 per primitive)");
    }
    enabled.resize(switches.size());
    for (std::size_t p = 0; p < switches.size(); ++p) enabled[p] = switches[p] != 0 ? 1 : 0;
  }
  QueryContext context;
  context.skip_primitive = skip;
  context.primitive_enabled = enabled;
  context.skip_geometry = skip_geometry;
  context.ray_mask = mask;
  context.geometry_mask = geometry_masks;
  context.geometry_starts = geometries.starts();

  std::vector<double> build_ms;
  double load_ms = 0.0;
  std::unique_ptr<Accelerator> accel;
  if (!args.load.empty()) {
    const Stopwatch clock;
    accel = load_accelerator(args.load, scene);
    load_ms = clock.milliseconds();
  } else {
    for (int i = 0; i < kTraceBuilds; ++i) {
      accel = make_structure(spec, ThreadLimit::active());
      const Stopwatch clock;
      accel->build(scene);
      build_ms.push_back(clock.milliseconds());
    }
  }
  // --save and --out are written, then committed together: a failure of either leaves both as they were.
  OutputBatch outputs;
  if (!args.save.empty()) accel->save(outputs.stage(args.save));
  const std::string geometry_ids_path =
      args.geometry_ids.empty() ? std::string() : outputs.stage(args.geometry_ids).string();

  const TracePasses passes = run_trace_passes<Hit>(
      rays.size(), args.occlusion, args.repeat, args.out.empty() ? std::string() : outputs.stage(args.out).string(),
      [&](std::span<Hit> hits) {
        if (with_context && args.packets) {
          accel->intersect_packets(context, rays, hits);
        } else if (with_context) {
          accel->intersect(context, rays, hits);
        } else if (args.packets) {
          accel->intersect_packets(rays, hits);
        } else {
          accel->intersect(rays, hits);
        }
      },
      [&](std::span<std::uint8_t> occluded) {
        if (with_context && args.packets) {
          accel->occluded_packets(context, rays, occluded);
        } else if (with_context) {
          accel->occluded(context, rays, occluded);
        } else if (args.packets) {
          accel->occluded_packets(rays, occluded);
        } else {
          accel->occluded(rays, occluded);
        }
      },
      [&](const std::string& path, std::span<const Hit> hits) {
        write_hits(path, hits);
        if (geometry_ids_path.empty()) return;
        std::vector<std::uint32_t> ids(hits.size());
        geometries.geometry_ids(hits, ids);
        write_ids(geometry_ids_path, ids);
      });

  nlohmann::json summary = trace_summary({
      .accel = accel->spec(),
      .scene = scene.name(),
      .primitives = scene.primitive_count(),
      .rays = rays.size(),
      .query = args.occlusion ? (args.packets ? "occluded_packets" : "occluded")
                              : (args.packets ? "intersect_packets" : "intersect"),
      .trace_ms = passes.trace_ms,
      .hit_count = passes.hit_count,
      .memory_bytes = accel->memory_bytes(),
      .scene_memory_bytes = scene.memory_bytes(),
      .input_memory_bytes = accel->input_memory_bytes(scene),
  });
  if (args.load.empty()) {
    summary["build_ms_median"] = median(build_ms);
    summary["build_ms"] = build_ms;
  } else {
    summary["loaded_from"] = args.load;
    summary["load_ms"] = load_ms;
  }
  outputs.commit();
  if (!args.save.empty()) summary["saved_to"] = args.save;
  if (!args.out.empty()) summary["out"] = args.out;
  if (!args.skip.empty()) summary["skip"] = args.skip;
  if (!args.mask.empty()) summary["mask"] = args.mask;
  if (!args.skip_geometry.empty()) summary["skip_geometry"] = args.skip_geometry;
  if (!args.enabled.empty()) summary["enabled"] = args.enabled;
  if (!args.geometry_ids.empty()) summary["geometry_ids"] = args.geometry_ids;
  summary["geometries"] = geometries.geometry_count();
  fmt::print("{}\n", summary.dump());
  return 0;
}

}  // namespace

Command add_trace_command(CLI::App& root) {
  auto args = std::make_shared<TraceArgs>();
  CLI::App* app = root.add_subcommand("trace", "Trace a .rays file and write the .hits (or .occ) file");
  app->add_option("scene", args->scene, "Mesh file or builtin:NAME[:key=value,...]")->required();
  app->add_option("rays", args->rays,
                  ".rays file (32 bytes per ray: ox oy oz tmin dx dy dz tmax; .rays64, 64 bytes, with --precision "
                  "double)")
      ->required();
  app->add_option("--accel", args->accel,
                  "Structure spec NAME[:key=value,...] (see 'rayaccel list'); default " + default_accelerator_spec());
  app->add_flag("--occlusion", args->occlusion, "Any-hit queries (occluded()); writes a .occ file");
  app->add_flag("--packets", args->packets,
                "Coherent rays: each run of eight consecutive rays traced as one packet (intersect_packets(), or "
                "occluded_packets() with --occlusion; structures without a packet traversal trace them one by one)");
  CLI::Option* threads = app->add_option("--threads", args->threads, "Worker threads for build and trace (>= 1)");
  app->add_option("--repeat", args->repeat, "Timed passes over all rays (median reported)")->capture_default_str();
  app->add_option("--out", args->out, "Output .hits file (.hits64 with --precision double; .occ with --occlusion)");
  app->add_option("--precision", args->precision,
                  "float, or double: the double path (double vertices and rays, brute_force or bvh with bv=aabb)")
      ->check(CLI::IsMember({"float", "double"}))
      ->capture_default_str();
  app->add_option("--offset", args->offset,
                  "With --precision double: x,y,z added to every vertex in double (to place a model far away)");
  app->add_option("--save", args->save,
                  "Save the built structure to this file (bvh, every volume, and bvh_wide), to --load it later");
  app->add_option("--load", args->load,
                  "Load the structure saved by --save instead of building one (checked against the scene: a file "
                  "saved for other geometry is refused)");
  app->add_flag("--instances", args->instances,
                "Two-level trace: SCENE read with its instancing (a mesh reused by several nodes is traced once per "
                "node through one bottom level); --accel names the bottom levels' structure; --out writes .ihits "
                "(24 bytes per ray: t prim_id u v geom_id instance_id)");
  app->add_option("--geometry", args->geometries,
                  "With --instances: one more mesh file or builtin scene, placed with the identity beside SCENE "
                  "(repeatable)")
      ->allow_extra_args(false);
  app->add_option("--skip", args->skip,
                  "A .ids file (uint32 per ray, 0xFFFFFFFF: none): the primitive each ray ignores, e.g. the surface "
                  "it leaves; tested before the exact triangle test");
  app->add_option("--mask", args->mask,
                  "A .ids file of ray masks (uint32 per ray): a ray sees the scene when mask & --geometry-mask != 0");
  app->add_option("--geometry-mask", args->geometry_mask,
                  "M (every geometry's mask) or M0,M1,... (one per mesh of the scene file, numbered as --geometry-ids "
                  "numbers them): a ray sees geometry g when its --mask & M_g != 0; a mask of 0 hides a mesh");
  app->add_option("--skip-geometry", args->skip_geometry,
                  "A .ids file (uint32 per ray, 0xFFFFFFFF: none): the geometry (mesh) each ray ignores");
  app->add_option("--enabled", args->enabled,
                  "A .ids file with one uint32 per primitive of the scene: 0 hides the primitive from every ray "
                  "(cut-outs, an opacity threshold), nonzero keeps it");
  app->add_option("--geometry-ids", args->geometry_ids,
                  "With --out: write the geometry id of each hit (uint32 per ray, 0xFFFFFFFF for a miss), the mesh of "
                  "a scene file of several meshes in the file's scene-graph order (a PLY file or builtin: 0)");
  app->add_option("--top", args->top,
                  "With --instances: the top level, bvh_top (the BVH over instance boxes, the default) or any "
                  "structure spec, built over one user primitive per instance");
  return {app, [args, threads] { return run_trace(*args, threads->count() > 0); }};
}

}  // namespace rayaccel::cli
