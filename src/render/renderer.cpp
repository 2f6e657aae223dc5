// The renderer: primary rays in chunks of rows through an accelerator's batch API, then normal, ambient-occlusion
// or traversal-cost shading per pixel in parallel over rows.
#include "rayaccel/render/renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/generalized/generalized_rays.h"
#include "rayaccel/render/colormap.h"
#include "rayaccel/render/heatmap.h"
#include "rayaccel/render/sampling.h"
#include "rayaccel/render/shading.h"
#include "rayaccel/render/workloads.h"

namespace rayaccel {

namespace {

constexpr std::size_t kRaysPerChunk = std::size_t{1} << 15;  // enough rays per batch to keep every core busy
constexpr float kAoAlbedo = 0.8f;

void check_settings(const RenderSettings& settings) {
  if (settings.width <= 0 || settings.height <= 0) {
    throw Error("render: image size " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                " is not positive");
  }
  if (settings.mode != ShadingMode::ambient_occlusion) return;
  if (settings.ao_samples < 1) throw Error("render: ao_samples " + std::to_string(settings.ao_samples) + " < 1");
  if (settings.ao_max_samples != 0 && settings.ao_max_samples < settings.ao_samples) {
    throw Error("render: ao_max_samples " + std::to_string(settings.ao_max_samples) + " is below ao_samples " +
                std::to_string(settings.ao_samples) + " (0 turns adaptive sampling off)");
  }
  if (!(settings.ao_error >= 0.0f && settings.ao_error <= 0.5f)) {
    throw Error("render: ao_error " + std::to_string(settings.ao_error) + " is not in [0, 0.5]");
  }
  if (!(std::isfinite(settings.ao_distance_fraction) && settings.ao_distance_fraction >= 0.0f)) {
    throw Error("render: ao_distance_fraction " + std::to_string(settings.ao_distance_fraction) +
                " is not a finite value >= 0");
  }
}

/// Runs body(y) for every row in [y0, y1) in parallel.
template <class Body>
void for_rows(int y0, int y1, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<int>(y0, y1), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) body(y);
  });
}

class Timer {
 public:
  explicit Timer(double& total_ms) : total_ms_(total_ms), start_(std::chrono::steady_clock::now()) {}
  ~Timer() {
    total_ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }
  Timer(const Timer&) = delete;
  Timer& operator=(const Timer&) = delete;

 private:
  double& total_ms_;
  std::chrono::steady_clock::time_point start_;
};

/// One round of AO rays: `samples` rays from each hit of (rays, hits), seeds (chunk, round, sample); returns how
/// many of each hit's rays nothing blocks.
std::vector<int> unblocked_ao_rays(const Accelerator& accel, const Scene& scene, std::span<const Ray> rays,
                                   std::span<const Hit> hits, int samples, float max_distance,
                                   const RenderSettings& settings, std::uint64_t chunk, int round, RenderResult& result) {
  std::vector<Ray> batch;
  std::size_t hit_count = 0;
  for (int s = 0; s < samples; ++s) {
    // One seed per (chunk, round, sample): chunks depend only on the image width, so the rays never depend on threads.
    const auto dimension = static_cast<std::uint32_t>(round * 65536 + s);
    const std::vector<Ray> sample =
        shadow_rays(scene, rays, hits, max_distance, hash_counter(settings.seed, chunk, dimension));
    hit_count = sample.size();
    batch.insert(batch.end(), sample.begin(), sample.end());
  }
  std::vector<std::uint8_t> blocked(batch.size());
  std::vector<TraversalStats> stats(batch.size());
  {
    Timer timer(result.trace_milliseconds);
    accel.occluded(batch, blocked, stats);
  }
  result.rays += batch.size();
  for (const TraversalStats& st : stats) result.total += st;
  std::vector<int> open(hit_count, 0);
  for (std::size_t k = 0; k < hit_count; ++k) {
    for (int s = 0; s < samples; ++s) open[k] += blocked[s * hit_count + k] ? 0 : 1;
  }
  return open;
}

/// Fraction of each hit's AO rays that nothing blocks, for the hits of one chunk in order. With ao_max_samples
/// above ao_samples, hits whose estimate is still uncertain (standard error sqrt(p (1 - p) / n) above ao_error)
/// get further rounds of ao_samples rays, up to ao_max_samples: rays go where the estimate's variance is high.
std::vector<float> ambient_visibility(const Accelerator& accel, const Scene& scene, std::span<const Ray> rays,
                                      std::span<const Hit> hits, const RenderSettings& settings,
                                      std::uint64_t chunk, RenderResult& result) {
  const float diagonal_distance = settings.ao_distance_fraction * length(scene.bounds().extent());
  const float max_distance = std::isfinite(diagonal_distance) ? diagonal_distance : 0.0f;
  std::vector<int> open =
      unblocked_ao_rays(accel, scene, rays, hits, settings.ao_samples, max_distance, settings, chunk, 0, result);
  std::vector<int> taken(open.size(), settings.ao_samples);
  std::vector<std::size_t> hit_pixel;  // index into rays/hits of each hit, in hit order
  for (std::size_t i = 0; i < hits.size(); ++i) {
    if (hits[i].found()) hit_pixel.push_back(i);
  }
  const auto uncertain = [&](std::size_t k) {
    const double n = taken[k], p = open[k] / n;
    return taken[k] + settings.ao_samples <= settings.ao_max_samples &&
           std::sqrt(p * (1.0 - p) / n) > static_cast<double>(settings.ao_error);
  };
  for (int round = 1;; ++round) {
    std::vector<std::size_t> more;
    for (std::size_t k = 0; k < open.size(); ++k) {
      if (uncertain(k)) more.push_back(k);
    }
    if (more.empty()) break;
    std::vector<Ray> sub_rays(more.size());
    std::vector<Hit> sub_hits(more.size());
    for (std::size_t j = 0; j < more.size(); ++j) {
      sub_rays[j] = rays[hit_pixel[more[j]]];
      sub_hits[j] = hits[hit_pixel[more[j]]];
    }
    const std::vector<int> extra = unblocked_ao_rays(accel, scene, sub_rays, sub_hits, settings.ao_samples,
                                                     max_distance, settings, chunk, round, result);
    for (std::size_t j = 0; j < more.size(); ++j) {
      open[more[j]] += extra[j];
      taken[more[j]] += settings.ao_samples;
    }
  }
  std::vector<float> visible(open.size());
  for (std::size_t k = 0; k < open.size(); ++k) {
    visible[k] = static_cast<float>(open[k]) / static_cast<float>(taken[k]);
  }
  return visible;
}

HeatFrame heat_frame(const Scene& scene, int width, int height, std::span<const Ray> rays, std::span<const Hit> hits,
                     std::span<const TraversalStats> stats) {
  HeatFrame frame;
  frame.width = width;
  frame.height = height;
  frame.cost.resize(stats.size());
  frame.brightness.assign(stats.size(), 1.0f);
  for_rows(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * width + x;
      frame.cost[i] = traversal_cost(stats[i]);
      if (hits[i].found()) {
        const float facing = std::fabs(dot(geometric_normal(scene, rays[i], hits[i]), rays[i].direction));
        frame.brightness[i] = 0.6f + 0.3f * std::clamp(facing, 0.0f, 1.0f);
      }
    }
  });
  frame.range = cost_range(frame.cost);
  return frame;
}

}  // namespace

ShadingMode parse_shading_mode(std::string_view text) {
  if (text == "normals") return ShadingMode::normals;
  if (text == "ao") return ShadingMode::ambient_occlusion;
  if (text == "heatmap") return ShadingMode::heatmap;
  throw Error("unknown shading mode '" + std::string(text) + "' (known: normals, ao, heatmap)");
}

RenderResult render(const Accelerator& accel, const Scene& scene, const Camera& camera,
                    const RenderSettings& settings) {
  check_settings(settings);
  const int width = settings.width, height = settings.height;
  RenderResult result;
  result.image = Image::filled(width, height, kBackground);
  const std::vector<Ray> rays = primary_rays(camera, width, height);
  std::vector<Hit> hits(rays.size());
  std::vector<TraversalStats> stats(rays.size());
  result.rays = rays.size();
  if (settings.beams) {
    if (settings.mode == ShadingMode::heatmap) throw Error("render: beams give no per-pixel cost for a heat map");
    const auto beams = generalized::make_generalized_rays(accel, scene);
    const CameraFrame frame = camera.frame(width, height);
    // The rays made above (made and timed apart, as for single rays): ray_at gives only the tiles' corners.
    const generalized::PixelRays pixels{width, height, [&frame](float x, float y) { return frame.ray_at(x, y); },
                                        rays};
    Timer timer(result.trace_milliseconds);
    const generalized::BeamStats traced = beams->trace_beams(pixels, *settings.beams, hits);
    result.beam_stats = traced;
    result.total.nodes_visited += traced.beam_node_tests + traced.ray_node_visits;
    result.total.primitives_tested += traced.beam_primitive_tests + traced.ray_primitive_tests;
  }

  const int chunk_rows = static_cast<int>(std::max<std::size_t>(1, kRaysPerChunk / static_cast<std::size_t>(width)));
  for (int y0 = 0, chunk = 0; y0 < height; y0 += chunk_rows, ++chunk) {
    const int y1 = std::min(height, y0 + chunk_rows);
    const std::size_t first = static_cast<std::size_t>(y0) * width;
    const std::size_t count = static_cast<std::size_t>(y1 - y0) * width;
    const std::span<const Ray> chunk_rays(rays.data() + first, count);
    const std::span<Hit> chunk_hits(hits.data() + first, count);
    if (!settings.beams) {
      Timer timer(result.trace_milliseconds);
      accel.intersect(chunk_rays, chunk_hits, std::span<TraversalStats>(stats.data() + first, count));
    }
    if (settings.mode == ShadingMode::normals) {
      for_rows(y0, y1, [&](int y) {
        for (int x = 0; x < width; ++x) {
          const std::size_t i = static_cast<std::size_t>(y) * width + x;
          if (hits[i].found()) result.image.set(x, y, normal_colour(geometric_normal(scene, rays[i], hits[i])));
        }
      });
    } else if (settings.mode == ShadingMode::ambient_occlusion) {
      const std::vector<float> visible =
          ambient_visibility(accel, scene, chunk_rays, chunk_hits, settings, static_cast<std::uint64_t>(chunk), result);
      std::size_t k = 0;  // hits are numbered in pixel order, as shadow_rays() emits them
      for (std::size_t i = first; i < first + count; ++i) {
        if (!hits[i].found()) continue;
        const std::uint8_t grey = encode_srgb(kAoAlbedo * visible[k++]);
        result.image.set(static_cast<int>(i % width), static_cast<int>(i / width), {grey, grey, grey});
      }
    }
    if (settings.progress) settings.progress(static_cast<float>(y1) / static_cast<float>(height));
  }
  for (const TraversalStats& st : stats) result.total += st;
  if (settings.mode == ShadingMode::heatmap) {
    result.heat = heat_frame(scene, width, height, rays, hits, stats);
    result.image = draw_heat_frame(result.heat, settings.heat_scale.value_or(result.heat.range));
  }
  return result;
}

}  // namespace rayaccel
