// Internal to the packet traversals (wide_bvh_packets.cpp, wide_bvh_tiles.cpp): a packet's rays prepared eight lanes at a time (PacketLanes), the per-lane
// constants of the single-ray box and watertight triangle tests.
#pragma once

#include <array>
#include <cfloat>
#include <cstddef>
#include <limits>
#include <utility>

#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel::wide {

#if RAYACCEL_AVX_KERNELS
namespace {  // internal to the packet traversals' files

// One ray per lane of the eight-wide kernels' lane sets (Avx8, Avx8Masked), and one lane per child of the node those
// kernels test: the packet size, the lane count and the node width are the same number.
constexpr int kPacketSize = simd::Avx8::kWidth;
static_assert(kPacketSize == static_cast<int>(detail::kPacketSize), "a packet of the batch calls fills the lanes");
static_assert(sizeof(Node<kPacketSize>::child) / sizeof(std::uint32_t) == kPacketSize, "one child a lane");

/// A ray that is void (see PreparedRay): the lanes of a last, partial packet.
[[maybe_unused]] Ray void_ray() {
  Ray ray;
  ray.t_min = std::numeric_limits<float>::infinity();
  ray.t_max = -std::numeric_limits<float>::infinity();
  return ray;
}

template <std::size_t... I>
std::array<PreparedRay, sizeof...(I)> prepare_rays(const Ray* rays, std::index_sequence<I...>) {
  return {PreparedRay(rays[I])...};
}

RAYACCEL_LANE_CODE_BEGIN

/// The per-lane constants of a packet, computed eight lanes at a time: each lane holds what PreparedRay,
/// BoxTestOrigin and Hit::begin give its ray (the same float operations: 1/d, d[kx] / d[kz], ...), when the packet
/// takes the fast path: every active ray with t_min >= 0, no origin coordinate subnormal (BoxTestOrigin's shift),
/// and the same axes kx, ky, kz in the watertight test. `fast` is false otherwise, and the packet is prepared ray by
/// ray instead.
template <class S>
struct PacketLanes {
  using F = typename S::F;
  F origin[3], direction[3], inv_direction[3], t_min;
  alignas(32) float far[kPacketSize];  ///< Hit::begin's t: the exclusive far bound per lane
  int active = 0;                       ///< lanes with a ray that is not void
  bool fast = false;
  int axes[3] = {0, 1, 2};  ///< kx, ky, kz shared by the active rays (fast path only)
  simd::TrianglePacket<S> triangle;  ///< origin in the shared axes, shear and t_min per lane (fast path only)

  RAYACCEL_LANE_INLINE explicit PacketLanes(const Ray* rays) {
    static_assert(sizeof(Ray) == 8 * sizeof(float), "Ray is the record ox oy oz t_min dx dy dz t_max");
    alignas(32) float field[8][kPacketSize];  // field f of every lane's ray
    for (int i = 0; i < kPacketSize; ++i) {
      float r[8];
      std::memcpy(r, &rays[i], sizeof(Ray));
      for (int f = 0; f < 8; ++f) field[f][i] = r[f];
    }
    const F inf = S::set1(std::numeric_limits<float>::infinity());
    const F sign_bit = S::set1(-0.0f);
    const F zero = S::zero();
    F valid = S::all_ones();
    F nonzero = S::zero();
    for (int a = 0; a < 3; ++a) {
      origin[a] = S::load(field[a]);
      direction[a] = S::load(field[4 + a]);
      // readable_direction(): subnormal components read as zero of their sign, as PreparedRay reads them.
      const F subnormal_d = S::lt(S::and_not(sign_bit, direction[a]), S::set1(FLT_MIN));
      direction[a] = S::blend(direction[a], S::bit_and(sign_bit, direction[a]), subnormal_d);
      // is_valid_ray: finite components (|x| < inf is false for NaN), a nonzero direction
      valid = S::bit_and(valid, S::bit_and(S::lt(S::and_not(sign_bit, origin[a]), inf),
                                           S::lt(S::and_not(sign_bit, direction[a]), inf)));
      nonzero = S::bit_or(nonzero, S::neq(direction[a], zero));
    }
    const F ray_t_min = S::load(field[3]);
    const F ray_t_max = S::load(field[7]);
    valid = S::bit_and(S::bit_and(valid, nonzero), S::le(ray_t_min, ray_t_max));  // false for a NaN bound
    active = S::movemask(valid);
    t_min = S::blend(inf, ray_t_min, valid);
    alignas(32) float t_max[kPacketSize];
    S::store(t_max, S::blend(S::sub(zero, inf), ray_t_max, valid));
    for (int i = 0; i < kPacketSize; ++i) far[i] = next_float_up(t_max[i]);
    const F one = S::set1(1.0f);
    for (int a = 0; a < 3; ++a) inv_direction[a] = S::div(one, direction[a]);
    if (!active || (S::movemask(S::ge(t_min, zero)) & active) != active) return;
    // BoxTestOrigin moves subnormal origin coordinates (0 < |o| < FLT_MIN where 1/d is finite): not here.
    for (int a = 0; a < 3; ++a) {
      const F abs_o = S::and_not(sign_bit, origin[a]);
      const F subnormal = S::bit_and(S::bit_and(S::gt(abs_o, zero), S::lt(abs_o, S::set1(FLT_MIN))),
                                     S::lt(S::and_not(sign_bit, inv_direction[a]), inf));
      if (S::movemask(subnormal) & active) return;
    }
    // kz = max_axis(|d|) (ties to the lower axis), the same in every active lane, and the same sign of d[kz].
    const F ax = S::and_not(sign_bit, direction[0]), ay = S::and_not(sign_bit, direction[1]),
            az = S::and_not(sign_bit, direction[2]);
    const int x_max = S::movemask(S::bit_and(S::ge(ax, ay), S::ge(ax, az))) & active;
    const int y_max = S::movemask(S::ge(ay, az)) & active & ~x_max;
    const int kz = x_max == active ? 0 : y_max == active ? 1 : (x_max | y_max) == 0 ? 2 : -1;
    if (kz < 0) return;
    const int negative = S::movemask(S::lt(direction[kz], zero)) & active;
    if (negative != 0 && negative != active) return;
    axes[2] = kz;
    axes[0] = (kz + 1) % 3;
    axes[1] = (axes[0] + 1) % 3;
    if (negative) std::swap(axes[0], axes[1]);
    const F dz = direction[kz];  // nonzero in every active lane (the largest of a nonzero direction)
    for (int a = 0; a < 3; ++a) triangle.origin_k[a] = origin[axes[a]];
    triangle.shear_x = S::div(direction[axes[0]], dz);
    triangle.shear_y = S::div(direction[axes[1]], dz);
    triangle.shear_z = S::div(one, dz);
    // shear_error() of ray_triangle.h, lane by lane (the same operations, so the same bits).
    const F shear_absolute = S::set1(kShearAbsoluteError);
    const F gamma5 = S::set1(float_gamma(5));
    triangle.shear_error_x = S::add(S::mul(gamma5, S::and_not(sign_bit, triangle.shear_x)), shear_absolute);
    triangle.shear_error_y = S::add(S::mul(gamma5, S::and_not(sign_bit, triangle.shear_y)), shear_absolute);
    triangle.t_min = t_min;
    fast = true;
  }
};

/// The packet traversals' box test, a box given in each lane by its near and far plane on each axis: each lane's slab
/// entry (from t_min, into t_near) and exit (from `far_bound`) with BoxKernel::intersect's operations and its
/// widening for t_min >= 0 (no lane is shifted on the fast path); `meets`: the lanes where entry <= exit.
template <class S>
RAYACCEL_LANE_INLINE void slab_meets(const PacketLanes<S>& in, const typename S::F near_plane[3],
                                     const typename S::F far_plane[3], const typename S::F& far_bound,
                                     typename S::F& t_near, typename S::F& meets) {
  using F = typename S::F;
  t_near = in.t_min;
  F t_far = far_bound;
  for (int a = 0; a < 3; ++a) {
    const F t0 = S::mul(S::sub(near_plane[a], in.origin[a]), in.inv_direction[a]);
    const F t1 = S::mul(S::sub(far_plane[a], in.origin[a]), in.inv_direction[a]);
    t_near = S::max(t0, t_near);  // NaN in t0 keeps the running bound, as in BoxKernel::intersect
    t_far = S::min(t1, t_far);
  }
  t_near = S::mul(t_near, S::set1(kSlabWidenDown));
  meets = S::le(t_near, S::mul(t_far, S::set1(kSlabWidenUp)));
}
RAYACCEL_LANE_CODE_END

}  // namespace
#endif  // RAYACCEL_AVX_KERNELS

}  // namespace rayaccel::wide
