// Beam tracer configuration checks, statistics and the image's pixel rays.
#include "rayaccel/generalized/beam_tracer.h"

#include <atomic>
#include <limits>
#include <string>

#include "rayaccel/accel/option_table.h"

namespace rayaccel::generalized {

namespace {

const OptionTable<BeamOptions>& beam_option_table() {
  using O = BeamOptions;
  static const OptionTable<O> table = [] {
    OptionTable<O> t("beams");
    t.integer("tile_size", &O::tile_size, 1, std::numeric_limits<int>::max(), "side of the first beams in pixels");
    t.integer("min_tile", &O::min_tile, 1, std::numeric_limits<int>::max(), "beams are not split below this side");
    t.boolean("entry_points", &O::entry_points, "rays left over start at the tile's entry node (false: the root)");
    t.boolean("frustum", &O::frustum,
              "bvh_wide: SIMD float frustum culling with entry points (false: the double-precision beam tests)");
    t.boolean("packets", &O::packets,
              "bvh_wide frustum beams: the rays left over in 4 x 2 packets (false: one by one, with statistics)");
    t.boolean("tile_packets", &O::tile_packets,
              "with packets: each 8 x 8 block's packets traced together under the tile's frustum (false: one by one)");
    t.integer("max_front_candidates", &O::max_front_candidates, 0, std::numeric_limits<int>::max(),
              "the in-front proof is tried only up to this many candidates");
    t.real("max_candidates_per_pixel", &O::max_candidates_per_pixel, RealRange::at_least(0.0),
           "a beam with more candidates per pixel is not split");
    return t;
  }();
  return table;
}

}  // namespace

void check_options(const BeamOptions& config) { beam_option_table().check(config); }

BeamStats& BeamStats::operator+=(const BeamStats& o) {
  beams += o.beams;
  beam_node_tests += o.beam_node_tests;
  beam_primitive_tests += o.beam_primitive_tests;
  ray_node_visits += o.ray_node_visits;
  ray_primitive_tests += o.ray_primitive_tests;
  pixels_missed += o.pixels_missed;
  pixels_one_primitive += o.pixels_one_primitive;
  pixels_in_front += o.pixels_in_front;
  pixels_traced += o.pixels_traced;
  pixels_in_packets += o.pixels_in_packets;
  pixels_retraced += o.pixels_retraced;
  return *this;
}

namespace beam_detail {

std::span<const Ray> pixel_rays(const PixelRays& pixels, std::vector<Ray>& made, bool check_given_origins) {
  if (pixels.width <= 0 || pixels.height <= 0) {
    throw Error("beams: image size " + std::to_string(pixels.width) + "x" + std::to_string(pixels.height) +
                " is not positive");
  }
  if (!pixels.ray_at) throw Error("beams: no ray_at function for the pixels");
  const std::size_t count = std::size_t(pixels.width) * std::size_t(pixels.height);
  const bool given = !pixels.rays.empty();
  if (given && pixels.rays.size() != count) {
    throw Error("beams: " + std::to_string(pixels.rays.size()) + " rays given for " + std::to_string(count) +
                " pixels");
  }
  if (given && !check_given_origins) return pixels.rays;
  if (!given) made.resize(count);
  const std::span<const Ray> rays = given ? pixels.rays : std::span<const Ray>(made);
  // Rows in parallel (a trace is timed with them): ray_at may be called from several threads at once.
  const Vec3 origin = given ? rays[0].origin : pixels.ray_at(0.5f, 0.5f).origin;
  std::atomic<bool> shared_origin = true;
  ::rayaccel::detail::parallel_for_rays(std::size_t(pixels.height), [&](std::size_t begin, std::size_t end) {
    bool same = true;
    for (std::size_t y = begin; y < end; ++y) {
      const std::size_t row = y * std::size_t(pixels.width);
      for (int x = 0; x < pixels.width; ++x) {
        if (!given) made[row + std::size_t(x)] = pixels.ray_at(float(x) + 0.5f, float(y) + 0.5f);
        same = same && rays[row + std::size_t(x)].origin == origin;
      }
    }
    if (!same) shared_origin = false;
  });
  if (!shared_origin) throw Error("beams: the pixel rays do not share one origin");
  return rays;
}

void require_shared_origin(std::span<const Ray> rays, int width, int x0, int y0, int x1, int y1) {
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      if (!(rays[std::size_t(y) * std::size_t(width) + std::size_t(x)].origin == rays[0].origin)) {
        throw Error("beams: the pixel rays do not share one origin (pixel " + std::to_string(x) + ", " +
                    std::to_string(y) + ")");
      }
    }
  }
}

void check_hits_size(const PixelRays& pixels, std::size_t hits) {
  const std::size_t count = std::size_t(pixels.width) * std::size_t(pixels.height);
  if (hits != count) {
    throw Error("beams: " + std::to_string(hits) + " hits for " + std::to_string(count) + " pixels");
  }
}

}  // namespace beam_detail

}  // namespace rayaccel::generalized
