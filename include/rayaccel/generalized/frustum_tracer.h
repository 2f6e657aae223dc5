// Beams over the wide BVH by SIMD frustum culling with entry points found once per tile (Reshetov, Soupikov & Hurley
// 2005, "Multi-level ray tracing algorithm"; Wald et al. 2006 frustum culling): no primitive tests, only boxes.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/core/stats.h"
#include "rayaccel/wide/beam_frustum.h"
#include "rayaccel/generalized/beam_tracer.h"
#include "rayaccel/generalized/structure_views.h"
#include "rayaccel/simd/dispatch.h"

namespace rayaccel::generalized::beam_detail {

using wide::BeamFrustum;
using wide::frustum_child_lanes;
using wide::holds_lanes;

/// The frustum from `apex` through the corners of tile [x0, x1) x [y0, y1) (not yet proven to hold its rays).
inline BeamFrustum corner_frustum(const PixelRays& pixels, const Vec3& apex, int x0, int y0, int x1, int y1) {
  const float fx[4] = {float(x0), float(x1), float(x1), float(x0)};
  const float fy[4] = {float(y0), float(y0), float(y1), float(y1)};
  Vec3 corners[4];
  for (int i = 0; i < 4; ++i) corners[i] = pixels.ray_at(fx[i], fy[i]).direction;
  return BeamFrustum::through(apex, corners);
}

/// Every pixel of tile [x0, x1) x [y0, y1) of a `width`-wide image a miss (an empty frustum), counted in `stats`.
inline void mark_misses(std::span<Hit> hits, int width, int x0, int y0, int x1, int y1, BeamStats& stats) {
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) hits[std::size_t(y) * std::size_t(width) + std::size_t(x)] = Hit{};
  }
  stats.pixels_missed += std::uint64_t(x1 - x0) * std::uint64_t(y1 - y0);
}

// Each tile's frustum (BeamFrustum: float planes through its corner rays, every pixel ray proven inside) descends the
// wide BVH from its start node while exactly one child of a node may meet it, each node's W child boxes tested
// against every plane in one pass of W lanes. No child: every pixel misses. Otherwise the node reached is the tile's
// entry point: a tile above min_tile is split in four, each quarter descending from there; the rays of a tile at
// min_tile (or of one that reached a leaf) are traced from it with the structure's own traversals: in 4 x 2 pixel
// packets where it has them (eight-wide nodes), else one by one. A subtree the frustum culls holds nothing its rays
// can hit, so a traversal from the entry point tests the primitives that can be hit in the order one from the root
// does: every pixel's hit is intersect()'s bit for bit (a packet's ray that may have met a tie in t, where the packet
// could keep another primitive than intersect(), is traced again alone).
template <int W>
class FrustumTileTracer {
 public:
  FrustumTileTracer(const WideView<W>& view, const PixelRays& pixels, std::span<const Ray> rays,
                    const BeamOptions& config, std::span<Hit> hits)
      : view_(view), pixels_(pixels), rays_(rays), config_(config), hits_(hits) {}

  /// Resolves every pixel of the tile [x0, x1) x [y0, y1), splitting it as described above.
  void resolve(int x0, int y0, int x1, int y1, BeamStats& stats) const {
    simd::run_with_lanes(view_.isa(), [&]<class Lanes>() RAYACCEL_LANE_LAMBDA {
      if constexpr (Lanes::kWidth == W) resolve_with<Lanes>(x0, y0, x1, y1, stats);
    });
  }

 private:
  struct Tile {
    int x0, y0, x1, y1;
    std::uint32_t start;
  };

  template <class S>
  RAYACCEL_LANE_INLINE void resolve_with(int x0, int y0, int x1, int y1, BeamStats& stats) const {
    Tile pending[100];  // depth-first: at most 3 quarters wait per level of at most 32 levels
    int top = 0;
    pending[top++] = {x0, y0, x1, y1, view_.root()};
    while (top > 0) {
      const Tile t = pending[--top];
      ++stats.beams;
      const int w = t.x1 - t.x0, h = t.y1 - t.y0;
      // A tile resolved whole from the root by the tile traversal leaves the proof that its frustum holds its rays
      // to that traversal, which proves each packet's lanes in SIMD (and to the empty case below); any other tile
      // proves every ray now.
      const bool proof_later = t.start == view_.root() && std::max(w, h) <= config_.min_tile && tile_packets();
      BeamFrustum frustum = corner_frustum(pixels_, rays_[0].origin, t.x0, t.y0, t.x1, t.y1);
      if (frustum.valid() && !proof_later && !holds_every_ray<S>(frustum, t)) frustum.plane_count = 0;
      if (!frustum.valid()) {  // a frustum that cannot be proven to hold its rays decides nothing
        require_shared_origin(t);
        trace_rays(t, t.start, stats);
        continue;
      }
      std::uint32_t ref = t.start;
      bool empty = false;
      while (!view_.is_leaf(ref)) {
        const int lanes = frustum_child_lanes<S, W>(frustum, view_.node(ref));
        ++stats.beam_node_tests;
        if (lanes == 0) {
          empty = true;
          break;
        }
        if (lanes & (lanes - 1)) break;  // two or more children: the entry point
        ref = view_.node(ref).child[std::countr_zero(unsigned(lanes))];
      }
      if (empty && proof_later && !holds_every_ray<S>(frustum, t)) {
        require_shared_origin(t);
        trace_rays(t, t.start, stats);  // the root: the walk proved nothing
        continue;
      }
      if (empty) {
        mark_misses(hits_, pixels_.width, t.x0, t.y0, t.x1, t.y1, stats);
        continue;
      }
      if (view_.is_leaf(ref) || std::max(w, h) <= config_.min_tile) {
        trace_rays(t, config_.entry_points ? ref : view_.root(), stats, &frustum, !proof_later);
        continue;
      }
      const int xm = w > config_.min_tile ? t.x0 + (w + 1) / 2 : t.x1;
      const int ym = h > config_.min_tile ? t.y0 + (h + 1) / 2 : t.y1;
      // Pushed in reverse so the top-left quarter is resolved first.
      const Tile quarters[4] = {{xm, ym, t.x1, t.y1, ref}, {t.x0, ym, xm, t.y1, ref}, {xm, t.y0, t.x1, ym, ref},
                                {t.x0, t.y0, xm, ym, ref}};
      for (const Tile& q : quarters) {
        if (q.x0 < q.x1 && q.y0 < q.y1) pending[top++] = q;
      }
    }
  }

  /// Every tile's rays start at one origin where a frustum proved them inside (its apex is rays_[0]'s origin); where
  /// none did, this checks them (trace_frustum_beams() leaves the check of given rays to the tracer).
  void require_shared_origin(const Tile& t) const {
    beam_detail::require_shared_origin(rays_, pixels_.width, t.x0, t.y0, t.x1, t.y1);
  }

  /// True when the tile traversal runs (packets of eight-wide nodes, tiles together).
  bool tile_packets() const { return config_.packets && config_.tile_packets && view_.has_packets(); }

  /// True when every pixel ray of the tile is proven inside the valid `frustum`: W rays of a row at a time by the
  /// float test (holds_lanes()), the lanes it leaves out by holds().
  template <class S>
  RAYACCEL_LANE_INLINE bool holds_every_ray(const BeamFrustum& frustum, const Tile& t) const {
    for (int y = t.y0; y < t.y1; ++y) {
      for (int x = t.x0; x < t.x1; x += W) {
        const int count = std::min(W, t.x1 - x);
        const Ray* row = rays_.data() + index(x, y);
        const int proven = holds_lanes<S>(frustum, row, count);
        for (int rest = ~proven & ((1 << count) - 1); rest; rest &= rest - 1) {
          if (!frustum.holds(row[std::countr_zero(unsigned(rest))])) return false;
        }
      }
    }
    return true;
  }

  /// The rays of tile t from `start`. `frustum`: null, or the tile's frustum, `proven` to hold its rays or not (then
  /// only with tile_packets(), `start` found by its walk from the root).
  void trace_rays(const Tile& t, std::uint32_t start, BeamStats& stats, const BeamFrustum* frustum = nullptr,
                  bool proven = true) const {
    if (config_.packets && view_.has_packets()) {
      if (frustum != nullptr && config_.tile_packets) {
        trace_tile_packets(t, start, *frustum, proven, stats);
      } else {
        trace_packets(t, start, stats);
      }
      return;
    }
    beam_detail::trace_pixels_from(view_, start, t.x0, t.y0, t.x1, t.y1, pixels_.width, rays_.data(), hits_.data(),
                                   stats);
  }

  /// The tile's rays in 8 x 8 pixel blocks of eight 4 x 2 pixel packets, each block traced together from `start`
  /// under the tile's frustum (WideBvh::intersect_tile_from(), which proves its lanes unless `proven`); a block off
  /// that path packet by packet, from `start` where the frustum holds every ray, else from the root. The rays named
  /// as possibly tied are traced again alone.
  void trace_tile_packets(const Tile& t, std::uint32_t start, const BeamFrustum& frustum, bool proven,
                          BeamStats& stats) const {
    // Filled before use (left uninitialised: zeroing 3 kB a tile showed in profiles).
    union Rays {
      Rays() {}
      Ray ray[64];
    } block_storage;
    union Hits {
      Hits() {}
      Hit hit[64];
    } hit_storage;
    Ray* const block_rays = block_storage.ray;
    Hit* const block_hits = hit_storage.hit;
    std::size_t pixel[64];
    constexpr std::size_t kNoPixel = ~std::size_t(0);
    Ray void_ray;
    void_ray.t_min = std::numeric_limits<float>::infinity();
    void_ray.t_max = -std::numeric_limits<float>::infinity();
    TraversalStats retraced;
    for (int by = t.y0; by < t.y1; by += 8) {
      for (int bx = t.x0; bx < t.x1; bx += 8) {
        int count = 0;
        for (int py = by; py < std::min(by + 8, t.y1); py += 2) {
          for (int px = bx; px < std::min(bx + 8, t.x1); px += 4) {
            for (int dy = 0; dy < 2; ++dy) {
              for (int dx = 0; dx < 4; ++dx) {
                const bool inside = py + dy < t.y1 && px + dx < t.x1;
                pixel[count] = inside ? index(px + dx, py + dy) : kNoPixel;
                block_rays[count] = inside ? rays_[pixel[count]] : void_ray;
                ++count;
              }
            }
          }
        }
        std::uint64_t again = 0;
        const int refused = view_.trace_tile_from(start, frustum, block_rays, count, block_hits, again, !proven);
        // A refused packet alone: from `start` where the frustum holds its rays, else from the root.
        std::uint32_t from[8];
        for (int p = 0; p < count / 8; ++p) {
          from[p] = start;
          if (!(refused >> p & 1)) continue;
          bool held = true;
          for (int j = 8 * p; j < 8 * p + 8 && held && !proven; ++j) {
            held = pixel[j] == kNoPixel || frustum.holds(block_rays[j]);
          }
          if (!held) require_shared_origin(t);
          from[p] = held ? start : view_.root();
          again |= std::uint64_t(unsigned(view_.trace_packet_from(from[p], block_rays + 8 * p, 8, block_hits + 8 * p)))
                   << (8 * p);
        }
        for (int i = 0; i < count; ++i) {
          if (pixel[i] != kNoPixel) hits_[pixel[i]] = block_hits[i];
        }
        for (std::uint64_t rest = again; rest; rest &= rest - 1) {
          const int i = std::countr_zero(rest);
          if (pixel[i] == kNoPixel) continue;
          hits_[pixel[i]] = trace_alone(view_, from[i / 8], block_rays[i], retraced);
          ++stats.pixels_retraced;
        }
      }
    }
    const std::uint64_t pixels = std::uint64_t(t.x1 - t.x0) * std::uint64_t(t.y1 - t.y0);
    stats.pixels_traced += pixels;
    stats.pixels_in_packets += pixels;
    stats.ray_node_visits += retraced.nodes_visited;
    stats.ray_primitive_tests += retraced.primitives_tested;
  }

  /// The tile's rays in packets of 4 x 2 pixels (fewer at its right and bottom edges) from `start`; the rays a
  /// packet names as possibly tied are traced again alone.
  void trace_packets(const Tile& t, std::uint32_t start, BeamStats& stats) const {
    Ray packet[8];
    Hit packet_hits[8];
    std::size_t pixel[8];
    TraversalStats retraced;
    for (int y = t.y0; y < t.y1; y += 2) {
      for (int x = t.x0; x < t.x1; x += 4) {
        int count = 0;
        for (int dy = 0; dy < 2 && y + dy < t.y1; ++dy) {
          for (int dx = 0; dx < 4 && x + dx < t.x1; ++dx) {
            pixel[count] = index(x + dx, y + dy);
            packet[count] = rays_[pixel[count]];
            ++count;
          }
        }
        const int again = view_.trace_packet_from(start, packet, count, packet_hits);
        for (int i = 0; i < count; ++i) hits_[pixel[i]] = packet_hits[i];
        for (int rest = again; rest; rest &= rest - 1) {
          const int i = std::countr_zero(unsigned(rest));
          hits_[pixel[i]] = trace_alone(view_, start, packet[i], retraced);
        }
        stats.pixels_retraced += std::uint64_t(std::popcount(unsigned(again)));
      }
    }
    const std::uint64_t pixels = std::uint64_t(t.x1 - t.x0) * std::uint64_t(t.y1 - t.y0);
    stats.pixels_traced += pixels;
    stats.pixels_in_packets += pixels;
    stats.ray_node_visits += retraced.nodes_visited;
    stats.ray_primitive_tests += retraced.primitives_tested;
  }

  std::size_t index(int x, int y) const { return std::size_t(y) * std::size_t(pixels_.width) + std::size_t(x); }

  const WideView<W>& view_;
  const PixelRays& pixels_;
  std::span<const Ray> rays_;
  const BeamOptions& config_;
  std::span<Hit> hits_;
};

/// A frustum as a region of structure_views.h: box_outside() by BeamFrustum::box_outside() (its own slack, so the
/// view's is not added), a ball by its box rounded outward.
struct FrustumRegion {
  const BeamFrustum& frustum;
  bool box_outside(const AABB& box, float /*slack*/) const { return frustum.box_outside(box); }
  bool sphere_outside(const Vec3& center, float radius) const {
    const float inf = std::numeric_limits<float>::infinity();
    AABB box;
    for (int k = 0; k < 3; ++k) {
      box.lo[k] = std::nextafter(center[k] - radius, -inf);
      box.hi[k] = std::nextafter(center[k] + radius, inf);
    }
    return frustum.box_outside(box);
  }
};

/// The frustum beams over the other structures (Bvh<BV> with every volume, the kd-tree): the same tiles, frustum,
/// proof and entry-point walk as FrustumTileTracer, each node's children tested one box at a time (the planes in SSE
/// lanes, BeamFrustum::box_outside()), every ray proven inside by holds(); the rays left over traced one by one from
/// the entry point with the structure's own traversal. No primitive tests.
template <class View>
class FrustumViewTracer {
 public:
  using Ref = typename View::Ref;
  FrustumViewTracer(const View& view, const PixelRays& pixels, std::span<const Ray> rays, const BeamOptions& config,
                    std::span<Hit> hits)
      : view_(view), pixels_(pixels), rays_(rays), config_(config), hits_(hits) {}

  void resolve(int x0, int y0, int x1, int y1, BeamStats& stats) const {
    struct Tile {
      int x0, y0, x1, y1;
      Ref start;
    };
    std::vector<Tile> pending{{x0, y0, x1, y1, view_.root()}};
    while (!pending.empty()) {
      const Tile t = pending.back();
      pending.pop_back();
      ++stats.beams;
      const BeamFrustum frustum = proven_frustum(t.x0, t.y0, t.x1, t.y1);
      if (!frustum.valid()) {  // a frustum that cannot be proven to hold its rays decides nothing
        trace_rays(t.x0, t.y0, t.x1, t.y1, t.start, stats);
        continue;
      }
      const FrustumRegion region{frustum};
      Ref ref = t.start;
      TraversalStats walk;
      bool empty = view_.outside(ref, region);
      while (!empty && !view_.is_leaf(ref)) {
        int met = 0;
        Ref only = ref;
        view_.for_each_child(ref, region, walk, [&](const Ref& child) {
          ++met;
          only = child;
        });
        if (met != 1) {
          empty = met == 0;
          break;
        }
        ref = only;
      }
      stats.beam_node_tests += walk.nodes_visited + 1;
      if (empty) {
        mark_misses(hits_, pixels_.width, t.x0, t.y0, t.x1, t.y1, stats);
        continue;
      }
      const int w = t.x1 - t.x0, h = t.y1 - t.y0;
      if (view_.is_leaf(ref) || std::max(w, h) <= config_.min_tile) {
        trace_rays(t.x0, t.y0, t.x1, t.y1, config_.entry_points ? ref : view_.root(), stats);
        continue;
      }
      const int xm = w > config_.min_tile ? t.x0 + (w + 1) / 2 : t.x1;
      const int ym = h > config_.min_tile ? t.y0 + (h + 1) / 2 : t.y1;
      // Pushed in reverse so the top-left quarter is resolved first.
      for (const Tile& q : {Tile{xm, ym, t.x1, t.y1, ref}, Tile{t.x0, ym, xm, t.y1, ref},
                            Tile{xm, t.y0, t.x1, ym, ref}, Tile{t.x0, t.y0, xm, ym, ref}}) {
        if (q.x0 < q.x1 && q.y0 < q.y1) pending.push_back(q);
      }
    }
  }

 private:
  /// The frustum through the tile's corners, or an invalid one when a pixel ray is not proven inside it.
  BeamFrustum proven_frustum(int x0, int y0, int x1, int y1) const {
    BeamFrustum frustum = corner_frustum(pixels_, rays_[0].origin, x0, y0, x1, y1);
    for (int y = y0; y < y1 && frustum.valid(); ++y) {
      for (int x = x0; x < x1; ++x) {
        if (!frustum.holds(rays_[index(x, y)])) {
          frustum.plane_count = 0;
          break;
        }
      }
    }
    return frustum;
  }

  void trace_rays(int x0, int y0, int x1, int y1, const Ref& start, BeamStats& stats) const {
    trace_pixels_from(view_, start, x0, y0, x1, y1, pixels_.width, rays_.data(), hits_.data(), stats);
  }

  std::size_t index(int x, int y) const { return std::size_t(y) * std::size_t(pixels_.width) + std::size_t(x); }

  const View& view_;
  const PixelRays& pixels_;
  std::span<const Ray> rays_;
  const BeamOptions& config_;
  std::span<Hit> hits_;
};

}  // namespace rayaccel::generalized::beam_detail

namespace rayaccel::generalized {

/// trace_beams() over any other structure by frustum culling (beam_detail::FrustumViewTracer): the same hits.
template <class View>
BeamStats trace_frustum_beams(const View& view, const PixelRays& pixels, const BeamOptions& config,
                              std::span<Hit> hits) {
  return beam_detail::trace_tiles(view, pixels, config, hits, [&](std::span<const Ray> rays, std::span<Hit> out) {
    const beam_detail::FrustumViewTracer<View> tracer(view, pixels, rays, config, out);
    return [tracer](int x0, int y0, int x1, int y1, BeamStats& stats) { tracer.resolve(x0, y0, x1, y1, stats); };
  });
}

/// trace_beams() over the wide BVH by frustum culling (beam_detail::FrustumTileTracer): the same hits.
template <int W>
BeamStats trace_frustum_beams(const WideView<W>& view, const PixelRays& pixels, const BeamOptions& config,
                              std::span<Hit> hits) {
  return beam_detail::trace_tiles(view, pixels, config, hits, [&](std::span<const Ray> rays, std::span<Hit> out) {
    const beam_detail::FrustumTileTracer<W> tracer(view, pixels, rays, config, out);
    return [tracer](int x0, int y0, int x1, int y1, BeamStats& stats) { tracer.resolve(x0, y0, x1, y1, stats); };
  }, /*tracer_checks_origins=*/true);
}

}  // namespace rayaccel::generalized
