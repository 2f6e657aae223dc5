// Primary visibility by beams (Heckbert & Hanrahan 1984) with the entry-point search of Reshetov, Soupikov & Hurley
// 2005: each image tile's beam walks the tree once; every pixel's hit is bit for bit the structure's intersect().
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/core/error.h"
#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/core/stats.h"
#include "rayaccel/generalized/beam.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel::generalized {

/// The rays of an image: width x height pixels; ray_at(x, y) is the ray through image-plane point (x, y) in pixels
/// ((0, 0) the top-left corner, pixel (i, j)'s center at (i + 0.5, j + 0.5)). Every ray must start at one origin.
struct PixelRays {
  int width = 0;
  int height = 0;
  std::function<Ray(float, float)> ray_at;
  /// Optional: every pixel's ray, row by row, ray_at(x + 0.5, y + 0.5) for pixel (x, y), made by the caller (a bench
  /// that times the tracing alone); empty: made from ray_at inside the call. ray_at still gives the tiles' corners.
  std::span<const Ray> rays;
};

struct BeamOptions {
  int tile_size = 8;           ///< side of the first beams in pixels, >= 1
  int min_tile = 8;            ///< beams are not split below this side; their undecided rays are traced one by one
  bool entry_points = true;    ///< rays left over start at the tile's entry node (false: at the root)
  int max_front_candidates = 12;  ///< the in-front proof (pairwise) is tried only up to this many candidates
  /// A beam with more candidates than this per pixel is not split: its rays are traced from its entry point at once
  /// (fine geometry, where every pixel sees other primitives, so smaller beams would only repeat the walk).
  float max_candidates_per_pixel = 0.5f;
  /// bvh_wide: SIMD float frustum culling of boxes with entry points (frustum_tracer.h), no primitive tests; false:
  /// the double-precision beam/box and beam/triangle tests of every other structure.
  bool frustum = true;
  /// bvh_wide's frustum beams: the rays left over are traced in 4 x 2 pixel packets from the entry point (eight-wide
  /// nodes), a ray whose packet hit may differ from intersect()'s at a tie traced again alone; false: one by one,
  /// with per-ray statistics.
  bool packets = true;
  /// With packets: the packets of each 8 x 8 pixel block traced together, every node's children culled by the
  /// tile's frustum once for all of them (WideBvh::intersect_tile_from()); false: packet by packet.
  bool tile_packets = true;
};
/// Checks a configuration; throws Error naming the bad value.
void check_options(const BeamOptions& config);

/// What tracing by beams cost and how the pixels were resolved.
struct BeamStats {
  std::uint64_t beams = 0;                  ///< beams traced (first tiles and split ones)
  std::uint64_t beam_node_tests = 0;        ///< volume tests against beams
  std::uint64_t beam_primitive_tests = 0;   ///< beam/primitive tests
  std::uint64_t ray_node_visits = 0;        ///< nodes entered by the rays traced one by one
  std::uint64_t ray_primitive_tests = 0;    ///< ray/primitive tests: rays traced one by one and one-primitive pixels
  std::uint64_t pixels_missed = 0;          ///< resolved as misses by an empty beam
  std::uint64_t pixels_one_primitive = 0;   ///< resolved by one ray/primitive test: the beam's only candidate
  std::uint64_t pixels_in_front = 0;        ///< resolved by one ray/primitive test: a hit on the proven front triangle
  std::uint64_t pixels_traced = 0;          ///< traced one by one or in packets (from the entry point)
  std::uint64_t pixels_in_packets = 0;      ///< of those, traced in packets (no node or primitive counts)
  std::uint64_t pixels_retraced = 0;        ///< of those, traced again alone: a possible tie in the packet
  BeamStats& operator+=(const BeamStats& o);
};

struct BeamResult {
  std::vector<Hit> hits;  ///< row-major, width * height, as intersect() gives them (misses finished)
  BeamStats stats;
};

/// Traces every pixel's ray by beams over `view` (structure_views.h) built over `scene`. Throws Error when the pixel
/// rays do not share one origin or the size is not positive.
template <class View>
BeamResult trace_beams(const View& view, const Scene& scene, const PixelRays& pixels, const BeamOptions& config);
/// The same into the caller's `hits` (width * height, row by row); returns the statistics.
template <class View>
BeamStats trace_beams(const View& view, const Scene& scene, const PixelRays& pixels, const BeamOptions& config,
                      std::span<Hit> hits);

namespace beam_detail {

/// One ray traced alone from node `start` of `view` with the structure's own traversal: intersect()'s hit for a ray
/// whose every possible hit lies under `start`.
template <class View, class Ref>
Hit trace_alone(const View& view, const Ref& start, const Ray& ray, TraversalStats& stats) {
  const PreparedRay prepared(ray);
  Hit hit = Hit::begin(prepared);
  if (!prepared.is_void()) view.trace_from(start, prepared, hit, stats);
  hit.finish();
  return hit;
}

/// Traces the pixels [x0, x1) x [y0, y1) of a `width`-wide image one ray at a time from node `start` of `view`,
/// writing their hits and adding their cost and count to `stats`: the rays a beam leaves undecided.
template <class View, class Ref>
void trace_pixels_from(const View& view, Ref start, int x0, int y0, int x1, int y1, int width, const Ray* rays,
                       Hit* hits, BeamStats& stats) {
  TraversalStats cost;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(width) + std::size_t(x);
      hits[i] = trace_alone(view, start, rays[i], cost);
    }
  }
  stats.ray_node_visits += cost.nodes_visited;
  stats.ray_primitive_tests += cost.primitives_tested;
  stats.pixels_traced += std::uint64_t(x1 - x0) * std::uint64_t(y1 - y0);
}

/// One tile's work: the rays are those of the whole image, the tile a rectangle of it.
template <class View>
class TileTracer {
 public:
  using Ref = typename View::Ref;
  TileTracer(const View& view, const Scene& scene, const PixelRays& pixels, std::span<const Ray> rays,
             const BeamOptions& config, std::span<Hit> hits)
      : view_(view), scene_(scene), pixels_(pixels), rays_(rays), config_(config), hits_(hits) {}

  void resolve(int x0, int y0, int x1, int y1, Ref start, BeamStats& stats) const {
    ++stats.beams;
    const Vec3 apex = rays_[0].origin;
    const float fx[4] = {float(x0), float(x1), float(x1), float(x0)};
    const float fy[4] = {float(y0), float(y0), float(y1), float(y1)};
    DVec3 edges[4];
    for (int i = 0; i < 4; ++i) edges[i] = to_d(pixels_.ray_at(fx[i], fy[i]).direction);
    const Beam beam = Beam::through(apex, edges, 4);
    bool contained = beam.valid();
    for (int y = y0; y < y1 && contained; ++y) {
      for (int x = x0; x < x1 && contained; ++x) contained = beam.contains(ray(x, y).direction);
    }
    if (!contained) {  // a beam that cannot be proven to hold its rays decides nothing
      trace_rays(x0, y0, x1, y1, start, stats);
      return;
    }
    Candidates found;
    TraversalStats beam_nodes;
    std::vector<Ref> path;
    if (!view_.outside(start, beam)) collect(beam, start, path, found, beam_nodes, stats);
    stats.beam_node_tests += beam_nodes.nodes_visited + 1;
    std::sort(found.prims.begin(), found.prims.end());
    found.prims.erase(std::unique(found.prims.begin(), found.prims.end()), found.prims.end());
    const std::uint64_t pixel_count = std::uint64_t(x1 - x0) * std::uint64_t(y1 - y0);
    if (found.prims.empty()) {
      for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) hits_[index(x, y)] = Hit{};
      }
      stats.pixels_missed += pixel_count;
      return;
    }
    const Ref entry = config_.entry_points ? found.prefix.back() : start;
    std::uint32_t front = kInvalidPrimId;
    if (found.prims.size() == 1) {
      front = found.prims[0];
    } else if (scene_.kind() == PrimitiveKind::triangles && found.prims.size() <= std::size_t(config_.max_front_candidates)) {
      front = front_triangle(beam, found.prims);
    }
    if (front != kInvalidPrimId) {
      // Alone, or proven in front: a ray that hits it gets exactly that hit from intersect(); a ray that misses it
      // hits nothing when it was alone, and is traced otherwise.
      const bool alone = found.prims.size() == 1;
      for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
          const PreparedRay prepared(ray(x, y));
          Hit hit = Hit::begin(prepared);
          ++stats.ray_primitive_tests;
          if (!prepared.is_void() && scene_.intersect(front, prepared, hit)) {
            hit.finish();
            hits_[index(x, y)] = hit;
            ++(alone ? stats.pixels_one_primitive : stats.pixels_in_front);
          } else if (alone) {
            hits_[index(x, y)] = Hit{};
            ++stats.pixels_one_primitive;
          } else {
            trace_rays(x, y, x + 1, y + 1, entry, stats);
          }
        }
      }
      return;
    }
    const int w = x1 - x0, h = y1 - y0;
    if (std::max(w, h) <= config_.min_tile ||
        double(found.prims.size()) > double(config_.max_candidates_per_pixel) * double(pixel_count)) {
      trace_rays(x0, y0, x1, y1, entry, stats);
      return;
    }
    const int xm = w > config_.min_tile ? x0 + (w + 1) / 2 : x1;
    const int ym = h > config_.min_tile ? y0 + (h + 1) / 2 : y1;
    for (const auto& [a, b, c, d] : {std::array<int, 4>{x0, y0, xm, ym}, std::array<int, 4>{xm, y0, x1, ym},
                                     std::array<int, 4>{x0, ym, xm, y1}, std::array<int, 4>{xm, ym, x1, y1}}) {
      if (a < c && b < d) resolve(a, b, c, d, entry, stats);
    }
  }

 private:
  struct Candidates {
    std::vector<std::uint32_t> prims;
    std::vector<Ref> prefix;  ///< common prefix of the paths to every leaf with a candidate: the entry point last
    bool any_leaf = false;
  };

  const Ray& ray(int x, int y) const { return rays_[index(x, y)]; }
  std::size_t index(int x, int y) const { return std::size_t(y) * std::size_t(pixels_.width) + std::size_t(x); }

  void collect(const Beam& beam, Ref ref, std::vector<Ref>& path, Candidates& found, TraversalStats& nodes,
               BeamStats& stats) const {
    path.push_back(ref);
    if (view_.is_leaf(ref)) {
      bool kept = false;
      const bool triangles = scene_.kind() == PrimitiveKind::triangles;
      view_.for_each_prim(ref, [&](std::uint32_t id) {
        ++stats.beam_primitive_tests;
        if (triangles) {
          const auto t = scene_.triangle(id);
          if (beam.triangle_outside(t[0], t[1], t[2])) return;
        }
        found.prims.push_back(id);
        kept = true;
      });
      if (kept) {
        if (!found.any_leaf) {
          found.prefix = path;
          found.any_leaf = true;
        } else {
          std::size_t common = 0;
          while (common < found.prefix.size() && common < path.size() && found.prefix[common] == path[common]) {
            ++common;
          }
          found.prefix.resize(common);
        }
      }
    } else {
      view_.for_each_child(ref, beam, nodes,
                           [&](Ref child) { collect(beam, child, path, found, nodes, stats); });
    }
    path.pop_back();
  }

  /// A candidate that every ray of the beam meets before any other candidate, or kInvalidPrimId.
  std::uint32_t front_triangle(const Beam& beam, const std::vector<std::uint32_t>& prims) const {
    for (const std::uint32_t t : prims) {
      const auto v = scene_.triangle(t);
      bool in_front = true;
      for (const std::uint32_t q : prims) {
        if (q == t) continue;
        if (!beam_front_of(beam, v[0], v[1], v[2], scene_.primitive_bounds(q))) {
          in_front = false;
          break;
        }
      }
      if (in_front) return t;
    }
    return kInvalidPrimId;
  }

  void trace_rays(int x0, int y0, int x1, int y1, Ref start, BeamStats& stats) const {
    trace_pixels_from(view_, start, x0, y0, x1, y1, pixels_.width, rays_.data(), hits_.data(), stats);
  }

  const View& view_;
  const Scene& scene_;
  const PixelRays& pixels_;
  std::span<const Ray> rays_;
  const BeamOptions& config_;
  std::span<Hit> hits_;
};

/// Every pixel's ray (pixel centers): pixels.rays when given (checked for its size), else made from ray_at into
/// `made`; checked to share one origin (given rays: unless `check_given_origins` is false, when the tracer checks
/// them). Throws Error otherwise, or when the size is not positive.
std::span<const Ray> pixel_rays(const PixelRays& pixels, std::vector<Ray>& made, bool check_given_origins = true);
/// Throws Error unless every ray of [x0, x1) x [y0, y1) of a `width`-wide image starts at rays[0]'s origin.
void require_shared_origin(std::span<const Ray> rays, int width, int x0, int y0, int x1, int y1);
/// Throws Error unless `hits` has one entry a pixel.
void check_hits_size(const PixelRays& pixels, std::size_t hits);

/// The image cut into square tiles of config.tile_size, resolved in parallel: make_resolve(rays, hits) gives the
/// tracer, resolve(x0, y0, x1, y1, stats) fills the hits of tile [x0, x1) x [y0, y1). `tracer_checks_origins`: the
/// tracer throws for given rays that do not share one origin (pixel_rays() does not read them all first).
template <class View, class MakeResolve>
BeamStats trace_tiles(const View& view, const PixelRays& pixels, const BeamOptions& config, std::span<Hit> hits,
                      const MakeResolve& make_resolve, bool tracer_checks_origins = false) {
  check_options(config);
  BeamStats total;
  std::vector<Ray> made;
  const std::span<const Ray> rays = pixel_rays(pixels, made, !tracer_checks_origins);
  check_hits_size(pixels, hits.size());
  if (view.empty()) {
    std::fill(hits.begin(), hits.end(), Hit{});
    return total;
  }
  const auto resolve = make_resolve(rays, hits);
  const int tiles_x = (pixels.width + config.tile_size - 1) / config.tile_size;
  const int tiles_y = (pixels.height + config.tile_size - 1) / config.tile_size;
  std::mutex merge;
  detail::parallel_for_rays(std::size_t(tiles_x) * std::size_t(tiles_y), [&](std::size_t begin, std::size_t end) {
    BeamStats local;
    for (std::size_t t = begin; t < end; ++t) {
      const int tx = int(t % std::size_t(tiles_x)), ty = int(t / std::size_t(tiles_x));
      const int x0 = tx * config.tile_size, y0 = ty * config.tile_size;
      resolve(x0, y0, std::min(x0 + config.tile_size, pixels.width), std::min(y0 + config.tile_size, pixels.height),
              local);
    }
    const std::lock_guard<std::mutex> lock(merge);
    total += local;
  });
  return total;
}

/// trace(hits) run on a new image of hits, returned with its statistics.
template <class Trace>
BeamResult into_new_hits(const PixelRays& pixels, const Trace& trace) {
  BeamResult result;
  result.hits.resize(std::size_t(std::max(pixels.width, 0)) * std::size_t(std::max(pixels.height, 0)));
  result.stats = trace(std::span<Hit>(result.hits));
  return result;
}

}  // namespace beam_detail

template <class View>
BeamStats trace_beams(const View& view, const Scene& scene, const PixelRays& pixels, const BeamOptions& config,
                      std::span<Hit> hits) {
  return beam_detail::trace_tiles(view, pixels, config, hits, [&](std::span<const Ray> rays, std::span<Hit> out) {
    const beam_detail::TileTracer<View> tracer(view, scene, pixels, rays, config, out);
    return [tracer, &view](int x0, int y0, int x1, int y1, BeamStats& stats) {
      tracer.resolve(x0, y0, x1, y1, view.root(), stats);
    };
  });
}

template <class View>
BeamResult trace_beams(const View& view, const Scene& scene, const PixelRays& pixels, const BeamOptions& config) {
  return beam_detail::into_new_hits(
      pixels, [&](std::span<Hit> hits) { return trace_beams(view, scene, pixels, config, hits); });
}

}  // namespace rayaccel::generalized
