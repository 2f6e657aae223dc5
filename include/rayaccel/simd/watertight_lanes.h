// The watertight ray/triangle test (Woop, Benthin, Wald 2013) in SIMD lanes, written once over a lane set (Sse4,
// Avx8): one ray against four or eight triangles of Triangle4 blocks, or one triangle against a packet of rays. Lane
// for lane the same float operations as geometry/ray_triangle.h, so results are bit-identical to the scalar kernel.
#pragma once

#include <cstdint>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/query_context.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/geometry/ray_triangle.h"
#include "rayaccel/simd/lane_set.h"
#include "rayaccel/simd/lanes_sse.h"
#include "rayaccel/simd/triangle4.h"

namespace rayaccel::simd {

RAYACCEL_LANE_CODE_BEGIN
/// Per-ray constants of the triangle test over S's lanes: the origin and shear in the ray's (kx, ky, kz) frame.
template <class S>
struct TrianglePacket {
  typename S::F origin_k[3];
  typename S::F shear_x, shear_y, shear_z, t_min;
  typename S::F shear_error_x, shear_error_y;  ///< shear_error() of shear_x, shear_y: the edge error bound's factors
  TrianglePacket() = default;  ///< for a packet of rays, one per lane (the packet traversal fills the lanes)
  RAYACCEL_LANE_INLINE explicit TrianglePacket(const PreparedRay& r)
      : origin_k{S::set1(component(r.origin, r.kx)), S::set1(component(r.origin, r.ky)),
                 S::set1(component(r.origin, r.kz))},
        shear_x(S::set1(r.shear_x)),
        shear_y(S::set1(r.shear_y)),
        shear_z(S::set1(r.shear_z)),
        t_min(S::set1(r.t_min)),
        shear_error_x(S::set1(shear_error(r.shear_x))),
        shear_error_y(S::set1(shear_error(r.shear_y))) {}
};

/// The float path of the watertight test in each of S's lanes, from the vertices relative to the ray origin and
/// sheared (px, py: x and y after the shear; pz: the unsheared kz component; vertices a, b, c = 0, 1, 2), with the
/// lane's shear_z, t_min and exclusive far bound. `decided_miss` marks lanes known to miss (padding, inactive rays).
/// Each lane performs the float operations of geometry/ray_triangle.h in the same order, so whether a lane is written
/// in terms of one ray and eight triangles (intersect_triangle_lanes) or one triangle and eight rays
/// (intersect_triangle_rays), the answers are bit-identical to the scalar kernel's.
template <class S>
struct WatertightLanes {
  using F = typename S::F;
  int hits = 0;     ///< lanes whose float path found a hit with t_min + error < t < far bound
  int on_edge = 0;  ///< lanes the scalar kernel finishes (an edge function near 0, outside the safe range, tiny depth)
  int ties = 0;     ///< with kTies: lanes whose float path found a hit at exactly t = t_far (a tie with the kept hit)
  F t, inv_det, ev, ew;  ///< for the lanes in `hits`: u = ev * inv_det, v = ew * inv_det

  /// Returns false (and leaves the lanes unset) when every lane is decided as a miss by the signs of its edge
  /// functions or by `decided_miss`. kTies: also sets `ties`.
  template <bool kTies = false>
  RAYACCEL_LANE_INLINE bool test(const F px[3], const F py[3], const F pz[3], const F& shear_error_x,
                                 const F& shear_error_y, const F& shear_z, const F& t_min, const F& t_far,
                                 const F& decided_miss) {
    // a = vertex 0, b = vertex 1, c = vertex 2, in the scalar kernel's names.
    const F eu = S::sub(S::mul(px[2], py[1]), S::mul(py[2], px[1]));
    ev = S::sub(S::mul(px[0], py[2]), S::mul(py[0], px[2]));
    ew = S::sub(S::mul(px[1], py[0]), S::mul(py[1], px[0]));
    // Largest magnitudes of the x, y and (unsheared) z coordinates, and the bound on the edge functions' error
    // (TriangleErrorBounds of ray_triangle.h, operation for operation). max returns its second operand when either
    // is NaN, so the running bound goes second.
    const F sign_bit = S::set1(-0.0f);
    F max_x = S::and_not(sign_bit, px[0]), max_y = S::and_not(sign_bit, py[0]), max_z = S::and_not(sign_bit, pz[0]);
    for (int v = 1; v < 3; ++v) {
      max_x = S::max(S::and_not(sign_bit, px[v]), max_x);
      max_y = S::max(S::and_not(sign_bit, py[v]), max_y);
      max_z = S::max(S::and_not(sign_bit, pz[v]), max_z);
    }
    const F gamma3 = S::set1(float_gamma(3));
    const F dx = S::add(S::mul(gamma3, max_x), S::mul(shear_error_x, max_z));
    const F dy = S::add(S::mul(gamma3, max_y), S::mul(shear_error_y, max_z));
    const F edge_error = S::add(
        S::mul(S::add(S::mul(S::mul(S::set1(2.0f * float_gamma(2)), max_x), max_y),
                      S::mul(S::set1(2.0f), S::add(S::add(S::mul(dx, max_y), S::mul(dy, max_x)), S::mul(dx, dy)))),
               S::set1(WatertightBounds::kSlack)),
        S::set1(WatertightBounds::kEdgeFloor));
    // Most tested triangles are missed, with edge functions of opposite signs beyond their error bound, which
    // decides them in any range (see ray_triangle.h): leave before anything else when no lane is left. min and max
    // return one of their operands, so a lane found mixed here has one edge function below -error and one above it.
    const F zero = S::zero();
    const F mixed_signs = S::bit_and(S::lt(S::min(eu, S::min(ev, ew)), S::sub(zero, edge_error)),
                                     S::gt(S::max(eu, S::max(ev, ew)), edge_error));
    const F decided = S::bit_or(mixed_signs, decided_miss);
    if (S::movemask(decided) == (1 << S::kWidth) - 1) return false;
    const F magnitude = S::max(max_x, S::max(max_y, max_z));
    const F det = S::add(S::add(eu, ev), ew);
    // Undecided lanes the float kernel cannot finish alone, all done by the scalar kernel: an edge function within
    // its error bound of zero or an error bound large against det (exact edge functions), or coordinates outside
    // the safe range (power-of-two rescaling).
    const F safe = S::bit_and(S::le(magnitude, S::set1(kShearSafeMax)), S::ge(magnitude, S::set1(kShearSafeMin)));
    const F in_band = S::bit_or(S::bit_or(S::le(S::and_not(sign_bit, eu), edge_error),
                                          S::le(S::and_not(sign_bit, ev), edge_error)),
                                S::le(S::and_not(sign_bit, ew), edge_error));
    const F ill_conditioned =
        S::ge(S::mul(edge_error, S::set1(WatertightBounds::kIllConditioned)), S::and_not(sign_bit, det));
    const F unsafe = S::and_not(safe, S::all_ones());
    // Depths too small for t in float (depth_in_float_range() of ray_triangle.h, with t_unscale = 1): the scalar
    // kernel computes t in double.
    const F depth_min = S::set1(WatertightBounds::kDepthMin);
    const F tiny_depth = S::and_not(
        S::bit_and(S::ge(max_z, depth_min), S::ge(S::mul(S::and_not(sign_bit, det), max_z), depth_min)),
        S::all_ones());
    on_edge = S::movemask(
        S::and_not(decided, S::bit_or(S::bit_or(S::bit_or(in_band, ill_conditioned), unsafe), tiny_depth)));
    // t as finish_sheared_triangle() computes it: the depth first, shear_z last.
    const F scaled_depth = S::add(S::add(S::mul(eu, pz[0]), S::mul(ev, pz[1])), S::mul(ew, pz[2]));
    inv_det = S::div(S::set1(1.0f), det);
    t = S::mul(S::mul(scaled_depth, inv_det), shear_z);
    // t must clear t_min by more than its error bound: t_error_bound() of ray_triangle.h, operation for operation
    // (so SIMD and scalar accept the same hits).
    const F hi_z = S::max(pz[0], S::max(pz[1], pz[2]));
    const F lo_z = S::min(pz[0], S::min(pz[1], pz[2]));
    const F depth_error = S::mul(
        S::add(S::mul(S::mul(S::mul(S::set1(3.0f), edge_error), S::and_not(sign_bit, inv_det)), S::sub(hi_z, lo_z)),
               S::mul(S::set1(float_gamma(12)), max_z)),
        S::set1(WatertightBounds::kSlack));
    const F t_error = S::mul(depth_error, S::and_not(sign_bit, shear_z));
    const F valid = S::and_not(
        decided, S::bit_and(S::neq(det, zero), S::bit_and(S::gt(t, S::add(t_min, t_error)), S::lt(t, t_far))));
    hits = S::movemask(valid) & ~on_edge;
    if constexpr (kTies) {
      const F tied = S::and_not(
          decided, S::bit_and(S::neq(det, zero), S::bit_and(S::gt(t, S::add(t_min, t_error)), S::eq(t, t_far))));
      ties = S::movemask(tied) & ~on_edge;
    }
    return true;
  }

  /// t, u and v of every lane (meaningful in the lanes of `hits`).
  RAYACCEL_LANE_INLINE void store_hits(float* t_lane, float* u_lane, float* v_lane) const {
    S::store(t_lane, t);
    S::store(u_lane, S::mul(ev, inv_det));
    S::store(v_lane, S::mul(ew, inv_det));
  }
};

/// The float path of the watertight test over the S::kWidth triangles of blocks[0 .. S::kWidth / 4) with the exclusive
/// far bound t_far (WatertightLanes::test: false when every lane surely misses).
template <class S>
RAYACCEL_LANE_INLINE bool test_triangle_lanes(const TrianglePacket<S>& ray, const PreparedRay& scalar_ray,
                                              const Triangle4* const* blocks, float t_far, WatertightLanes<S>& lanes) {
  using F = typename S::F;
  const int k[3] = {scalar_ray.kx, scalar_ray.ky, scalar_ray.kz};
  F px[3], py[3], pz[3];  // vertices relative to the origin, sheared: x, y; and the kz component
  for (int v = 0; v < 3; ++v) {
    const F ax = S::sub(S::load_vertex(blocks, v, k[0]), ray.origin_k[0]);
    const F ay = S::sub(S::load_vertex(blocks, v, k[1]), ray.origin_k[1]);
    const F az = S::sub(S::load_vertex(blocks, v, k[2]), ray.origin_k[2]);
    px[v] = S::sub(ax, S::mul(ray.shear_x, az));
    py[v] = S::sub(ay, S::mul(ray.shear_y, az));
    pz[v] = az;
  }
  return lanes.test(px, py, pz, ray.shear_error_x, ray.shear_error_y, ray.shear_z, ray.t_min, S::set1(t_far),
                    S::padding(blocks));
}

/// The lanes of blocks[0 .. S::kWidth / 4) whose triangle intersect_triangle() may hit with t in (t_min, t_far): those
/// the float path hits and those it leaves to the scalar kernel. Every other lane is a miss of the scalar kernel.
template <class S>
RAYACCEL_LANE_INLINE int candidate_triangle_lanes(const TrianglePacket<S>& ray, const PreparedRay& scalar_ray,
                                                  const Triangle4* const* blocks, float t_far) {
  WatertightLanes<S> lanes;
  if (!test_triangle_lanes(ray, scalar_ray, blocks, t_far, lanes)) return 0;
  return lanes.hits | lanes.on_edge;
}

/// The lanes of `candidates` (bit k: triangle k % 4 of blocks[k / 4]) that hold a triangle the context allows.
template <class Stats>
RAYACCEL_LANE_INLINE int allowed_lanes(const Stats& stats, const Triangle4* const* blocks, int candidates) {
  int out = 0;
  for (int rest = candidates; rest; rest &= rest - 1) {
    const int lane = __builtin_ctz(static_cast<unsigned>(rest));
    const std::uint32_t id = blocks[lane / 4]->prim_id[lane % 4];
    if (id != kInvalidPrimId && stats.allows(id)) out |= 1 << lane;
  }
  return out;
}

/// Tests the S::kWidth triangles of blocks[0 .. S::kWidth / 4); updates hit with the closest one in (t_min, hit.t).
/// Returns true on any update. Lanes the float path cannot decide go to the scalar kernel (see WatertightLanes).
/// With a query context (Stats is a ContextStats) ruled-out lanes never reach the scalar kernel or the hit, and the
/// filter sees each closer hit before it is kept. Rules that may rule out whole blocks (masks, switches) are asked of
/// every lane first and blocks with no lane left are not tested; a skipped primitive alone is asked of the lanes the
/// float test leaves (hits and undecided lanes: a few, where asking all eight lanes cost more than the test it saved).
template <class S, class Stats = NoStats>
RAYACCEL_LANE_INLINE bool intersect_triangle_lanes(const TrianglePacket<S>& ray, const PreparedRay& scalar_ray,
                                                   const Triangle4* const* blocks, Hit& hit,
                                                   const Stats& stats = {}) {
  constexpr int W = S::kWidth;
  [[maybe_unused]] int allowed = (1 << W) - 1;
  if constexpr (kHasContext<Stats>) {
    if (stats.rules_out_blocks()) {
      allowed = allowed_lanes(stats, blocks, allowed);
      if (allowed == 0) return false;
    }
  }
  WatertightLanes<S> lanes;
  if (!test_triangle_lanes(ray, scalar_ray, blocks, hit.t, lanes)) return false;
  int hit_lanes = lanes.hits, edge_lanes = lanes.on_edge;
  if constexpr (kHasContext<Stats>) {
    if (!stats.rules_out_blocks()) allowed = allowed_lanes(stats, blocks, hit_lanes | edge_lanes);
    hit_lanes &= allowed;
    edge_lanes &= allowed;
  }
  bool updated = false;
  if (hit_lanes) {
    float t_lane[W], u_lane[W], v_lane[W];
    lanes.store_hits(t_lane, u_lane, v_lane);
    for (int rest = hit_lanes; rest; rest &= rest - 1) {
      const int lane = __builtin_ctz(static_cast<unsigned>(rest));
      if (t_lane[lane] < hit.t) {
        const Hit candidate{t_lane[lane], blocks[lane / 4]->prim_id[lane % 4], u_lane[lane], v_lane[lane]};
        if constexpr (kHasContext<Stats>) {
          if (stats.has_filter() && !stats.accepts(candidate)) continue;
        }
        hit = candidate;
        updated = true;
      }
    }
  }
  for (int rest = edge_lanes; rest; rest &= rest - 1) {
    const int lane = __builtin_ctz(static_cast<unsigned>(rest));
    const Triangle4& block = *blocks[lane / 4];
    const int i = lane % 4;
    const Vec3 v0{block.vertex[0][0][i], block.vertex[0][1][i], block.vertex[0][2][i]};
    const Vec3 v1{block.vertex[1][0][i], block.vertex[1][1][i], block.vertex[1][2][i]};
    const Vec3 v2{block.vertex[2][0][i], block.vertex[2][1][i], block.vertex[2][2][i]};
    updated |= test_candidate(stats, block.prim_id[i], hit, [&](Hit& h) {
      return intersect_triangle(scalar_ray, v0, v1, v2, block.prim_id[i], h);
    });
  }
  return updated;
}

/// Sets the lanes of `t_far` named in `lanes` to their hits' t (a packet's far bounds after its hits changed).
template <class S>
RAYACCEL_LANE_INLINE void set_lanes_to_hits(typename S::F& t_far, int lanes, const Hit* hits) {
  alignas(32) float far[S::kWidth];
  S::store(far, t_far);
  for (int rest = lanes; rest; rest &= rest - 1) {
    const int lane = __builtin_ctz(static_cast<unsigned>(rest));
    far[lane] = hits[lane].t;
  }
  t_far = S::load(far);
}

/// Tests triangle `i` of `block` against the rays of a packet, one per lane of S, in the lanes set in `rays`: all of
/// them share the axes kx, ky, kz (`axes`), and `packet` holds each lane's own origin, shear and t_min, as
/// PreparedRay computes them from scalar_rays[lane] (which the scalar kernel gets for undecided lanes). Updates each
/// lane's hit (closest in (t_min, hit.t)) and the lanes of `t_far`, the packet's exclusive far bounds (hit.t per lane).
/// Returns the lanes whose hit changed. kTies: adds to *ties the lanes where this triangle may tie with the kept hit
/// (the float path found t equal to the lane's far bound, or the scalar kernel decided the lane), so that a caller
/// needing one tie rule can trace those rays again.
template <class S, bool kTies = false>
RAYACCEL_LANE_INLINE int intersect_triangle_rays(const TrianglePacket<S>& packet, const Ray* scalar_rays, int rays,
                                                 const int axes[3], const Triangle4& block, int i, Hit* hits,
                                                 typename S::F& t_far, int* ties = nullptr) {
  using F = typename S::F;
  constexpr int W = S::kWidth;
  F px[3], py[3], pz[3];
  for (int v = 0; v < 3; ++v) {
    const F ax = S::sub(S::broadcast(&block.vertex[v][axes[0]][i]), packet.origin_k[0]);
    const F ay = S::sub(S::broadcast(&block.vertex[v][axes[1]][i]), packet.origin_k[1]);
    const F az = S::sub(S::broadcast(&block.vertex[v][axes[2]][i]), packet.origin_k[2]);
    px[v] = S::sub(ax, S::mul(packet.shear_x, az));
    py[v] = S::sub(ay, S::mul(packet.shear_y, az));
    pz[v] = az;
  }
  WatertightLanes<S> lanes;
  const F inactive = S::and_not(S::lanes_from_bits(rays), S::all_ones());
  if (!lanes.template test<kTies>(px, py, pz, packet.shear_error_x, packet.shear_error_y, packet.shear_z,
                                  packet.t_min, t_far, inactive)) {
    return 0;
  }
  if constexpr (kTies) *ties |= lanes.ties | lanes.on_edge;
  const std::uint32_t prim_id = block.prim_id[i];
  int updated = 0;
  if (lanes.hits) {
    float t_lane[W], u_lane[W], v_lane[W];
    lanes.store_hits(t_lane, u_lane, v_lane);
    for (int rest = lanes.hits; rest; rest &= rest - 1) {
      const int lane = __builtin_ctz(static_cast<unsigned>(rest));
      hits[lane] = {t_lane[lane], prim_id, u_lane[lane], v_lane[lane]};  // t < hit.t: the lane's far bound
      updated |= 1 << lane;
    }
  }
  if (lanes.on_edge) {
    const Vec3 v0{block.vertex[0][0][i], block.vertex[0][1][i], block.vertex[0][2][i]};
    const Vec3 v1{block.vertex[1][0][i], block.vertex[1][1][i], block.vertex[1][2][i]};
    const Vec3 v2{block.vertex[2][0][i], block.vertex[2][1][i], block.vertex[2][2][i]};
    for (int rest = lanes.on_edge; rest; rest &= rest - 1) {
      const int lane = __builtin_ctz(static_cast<unsigned>(rest));
      if (intersect_triangle(PreparedRay(scalar_rays[lane]), v0, v1, v2, prim_id, hits[lane])) updated |= 1 << lane;
    }
  }
  if (updated) set_lanes_to_hits<S>(t_far, updated, hits);
  return updated;
}

/// Tests the four triangles of one block (see intersect_triangle_lanes).
template <class Stats = NoStats>
RAYACCEL_LANE_INLINE bool intersect_triangles4(const TrianglePacket<Sse4>& ray, const PreparedRay& scalar_ray,
                                               const Triangle4& tri, Hit& hit, const Stats& stats = {}) {
  const Triangle4* blocks[1] = {&tri};
  return intersect_triangle_lanes<Sse4>(ray, scalar_ray, blocks, hit, stats);
}
RAYACCEL_LANE_CODE_END

}  // namespace rayaccel::simd
