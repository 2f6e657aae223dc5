// Four-wide SSE kernels of the wide BVH: one ray against four child boxes (robust slab test, Ize 2013) and one ray
// against four triangles (the watertight test of Woop, Benthin, Wald 2013, lane-for-lane the same float operations as
// geometry/ray_triangle.h, so results are bit-identical to the scalar kernel).
#pragma once

#include <emmintrin.h>

#include <cstdint>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/geometry/ray_box.h"
#include "rayaccel/geometry/ray_triangle.h"
#include "rayaccel/wide/wide_node.h"

namespace rayaccel::wide {

/// Per-ray constants of the four-wide kernels, splatted once per ray.
struct RayPacket4 {
  __m128 origin[3];
  __m128 inv_direction[3];
  int near_offset[3];  ///< 0 when the near plane is lo (direction >= +0), 1 when it is hi
  __m128 t_min;
  // Triangle test: origin and shear in the ray's (kx, ky, kz) frame.
  __m128 origin_k[3];
  __m128 shear_x, shear_y, shear_z;

  explicit RayPacket4(const PreparedRay& r) {
    for (int a = 0; a < 3; ++a) {
      origin[a] = _mm_set1_ps(r.origin[a]);
      inv_direction[a] = _mm_set1_ps(r.inv_direction[a]);
      near_offset[a] = r.negative[a];
    }
    t_min = _mm_set1_ps(r.t_min);
    origin_k[0] = _mm_set1_ps(r.origin[r.kx]);
    origin_k[1] = _mm_set1_ps(r.origin[r.ky]);
    origin_k[2] = _mm_set1_ps(r.origin[r.kz]);
    shear_x = _mm_set1_ps(r.shear_x);
    shear_y = _mm_set1_ps(r.shear_y);
    shear_z = _mm_set1_ps(r.shear_z);
  }
};

/// Moves each lane away from the interval's inside by 2*gamma(3): toward -inf (down) or +inf (up). Monotone, so it
/// may be applied after the max/min reductions instead of to every slab distance.
inline __m128 widen_down(__m128 t) {
  const __m128 non_negative = _mm_cmpge_ps(t, _mm_setzero_ps());
  const __m128 factor = _mm_or_ps(_mm_and_ps(non_negative, _mm_set1_ps(kSlabWidenDown)),
                                  _mm_andnot_ps(non_negative, _mm_set1_ps(kSlabWidenUp)));
  return _mm_mul_ps(t, factor);
}
inline __m128 widen_up(__m128 t) {
  const __m128 non_negative = _mm_cmpge_ps(t, _mm_setzero_ps());
  const __m128 factor = _mm_or_ps(_mm_and_ps(non_negative, _mm_set1_ps(kSlabWidenUp)),
                                  _mm_andnot_ps(non_negative, _mm_set1_ps(kSlabWidenDown)));
  return _mm_mul_ps(t, factor);
}

/// Tests four boxes given as bounds[axis][0 = lo, 1 = hi][lane]. Returns the lane mask of boxes whose clipped
/// interval meets [t_min, t_far]; t_entry receives the entry distances. _mm_max_ps/_mm_min_ps return their second
/// operand when either is NaN, so the running bound goes second and a NaN slab distance (ray in a face plane)
/// constrains nothing, as in clip_ray_to_box().
inline int intersect_boxes4(const RayPacket4& ray, const float (*bounds)[2][4], __m128 t_far, __m128& t_entry) {
  __m128 t_near = ray.t_min;
  for (int a = 0; a < 3; ++a) {
    const __m128 near_plane = _mm_load_ps(bounds[a][ray.near_offset[a]]);
    const __m128 far_plane = _mm_load_ps(bounds[a][1 - ray.near_offset[a]]);
    const __m128 t0 = _mm_mul_ps(_mm_sub_ps(near_plane, ray.origin[a]), ray.inv_direction[a]);
    const __m128 t1 = _mm_mul_ps(_mm_sub_ps(far_plane, ray.origin[a]), ray.inv_direction[a]);
    t_near = _mm_max_ps(t0, t_near);
    t_far = _mm_min_ps(t1, t_far);
  }
  t_near = widen_down(t_near);
  t_far = widen_up(t_far);
  t_entry = t_near;
  return _mm_movemask_ps(_mm_cmple_ps(t_near, t_far));
}

/// The four-wide box test in the form the width-generic traversal calls (see BoxKernel8 for eight).
struct BoxKernel4 {
  static constexpr int kWidth = 4;
  using Packet = RayPacket4;
  static Packet prepare(const PreparedRay& r) { return RayPacket4(r); }
  static int intersect(const Packet& ray, const Node<4>& node, float t_far, float* t_entry) {
    __m128 entry;
    const int mask = intersect_boxes4(ray, node.bounds, _mm_set1_ps(t_far), entry);
    _mm_store_ps(t_entry, entry);
    return mask;
  }
};

/// Four triangles in SoA form: vertex[v][axis][lane]. Unused lanes hold prim kInvalidPrimId and a zero triangle
/// (a point, which the watertight test never hits).
struct alignas(16) Triangle4 {
  float vertex[3][3][4];
  std::uint32_t prim_id[4];
};
static_assert(sizeof(Triangle4) == 160, "Triangle4: 144 bytes of vertices + 16 bytes of ids");

/// Tests the four triangles; updates hit with the closest one in (t_min, hit.t). Returns true on any update.
inline bool intersect_triangles4(const RayPacket4& ray, const PreparedRay& scalar_ray, const Triangle4& tri,
                                 Hit& hit) {
  const int k[3] = {scalar_ray.kx, scalar_ray.ky, scalar_ray.kz};
  __m128 px[3], py[3], pz[3];  // vertices relative to the origin, sheared: x, y; and the kz component
  for (int v = 0; v < 3; ++v) {
    const __m128 ax = _mm_sub_ps(_mm_load_ps(tri.vertex[v][k[0]]), ray.origin_k[0]);
    const __m128 ay = _mm_sub_ps(_mm_load_ps(tri.vertex[v][k[1]]), ray.origin_k[1]);
    const __m128 az = _mm_sub_ps(_mm_load_ps(tri.vertex[v][k[2]]), ray.origin_k[2]);
    px[v] = _mm_sub_ps(ax, _mm_mul_ps(ray.shear_x, az));
    py[v] = _mm_sub_ps(ay, _mm_mul_ps(ray.shear_y, az));
    pz[v] = az;
  }
  // a = vertex 0, b = vertex 1, c = vertex 2, in the scalar kernel's names.
  const __m128 eu = _mm_sub_ps(_mm_mul_ps(px[2], py[1]), _mm_mul_ps(py[2], px[1]));
  const __m128 ev = _mm_sub_ps(_mm_mul_ps(px[0], py[2]), _mm_mul_ps(py[0], px[2]));
  const __m128 ew = _mm_sub_ps(_mm_mul_ps(px[1], py[0]), _mm_mul_ps(py[1], px[0]));
  const __m128 zero = _mm_setzero_ps();
  const __m128i padding = _mm_cmpeq_epi32(_mm_load_si128(reinterpret_cast<const __m128i*>(tri.prim_id)),
                                          _mm_set1_epi32(-1));
  // Lanes the float kernel cannot decide alone: an edge function of exactly zero (double-precision fallback) or
  // coordinates outside the safe range (power-of-two rescaling), both done by the scalar kernel.
  const __m128 sign_bit = _mm_set1_ps(-0.0f);
  __m128 magnitude = _mm_andnot_ps(sign_bit, pz[0]);
  for (int v = 0; v < 3; ++v) {
    magnitude = _mm_max_ps(_mm_andnot_ps(sign_bit, px[v]), magnitude);
    magnitude = _mm_max_ps(_mm_andnot_ps(sign_bit, py[v]), magnitude);
    magnitude = _mm_max_ps(_mm_andnot_ps(sign_bit, pz[v]), magnitude);
  }
  const __m128 safe = _mm_and_ps(_mm_cmple_ps(magnitude, _mm_set1_ps(kShearSafeMax)),
                                 _mm_cmpge_ps(magnitude, _mm_set1_ps(kShearSafeMin)));
  const __m128 on_edge_lanes =
      _mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(eu, zero), _mm_cmpeq_ps(ev, zero)), _mm_cmpeq_ps(ew, zero));
  const __m128 unsafe = _mm_andnot_ps(safe, _mm_castsi128_ps(_mm_set1_epi32(-1)));
  const int on_edge = _mm_movemask_ps(_mm_andnot_ps(_mm_castsi128_ps(padding), _mm_or_ps(on_edge_lanes, unsafe)));
  const __m128 any_negative =
      _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(eu, zero), _mm_cmplt_ps(ev, zero)), _mm_cmplt_ps(ew, zero));
  const __m128 any_positive =
      _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(eu, zero), _mm_cmpgt_ps(ev, zero)), _mm_cmpgt_ps(ew, zero));
  // Most tested triangles are missed: leave before the depth and the division when no lane can be hit.
  const __m128 mixed_signs = _mm_and_ps(any_negative, any_positive);
  if ((_mm_movemask_ps(_mm_andnot_ps(_mm_or_ps(mixed_signs, _mm_castsi128_ps(padding)),
                                     _mm_castsi128_ps(_mm_set1_epi32(-1)))) |
       on_edge) == 0) {
    return false;
  }
  const __m128 det = _mm_add_ps(_mm_add_ps(eu, ev), ew);
  const __m128 az = _mm_mul_ps(ray.shear_z, pz[0]);
  const __m128 bz = _mm_mul_ps(ray.shear_z, pz[1]);
  const __m128 cz = _mm_mul_ps(ray.shear_z, pz[2]);
  const __m128 scaled_t = _mm_add_ps(_mm_add_ps(_mm_mul_ps(eu, az), _mm_mul_ps(ev, bz)), _mm_mul_ps(ew, cz));
  const __m128 inv_det = _mm_div_ps(_mm_set1_ps(1.0f), det);
  const __m128 t = _mm_mul_ps(scaled_t, inv_det);
  const __m128 valid = _mm_andnot_ps(mixed_signs,
                                     _mm_and_ps(_mm_cmpneq_ps(det, zero),
                                                _mm_and_ps(_mm_cmpgt_ps(t, ray.t_min),
                                                           _mm_cmplt_ps(t, _mm_set1_ps(hit.t)))));
  int lanes = _mm_movemask_ps(valid) & ~on_edge;
  bool updated = false;
  if (lanes) {
    alignas(16) float t_lane[4], u_lane[4], v_lane[4];
    _mm_store_ps(t_lane, t);
    _mm_store_ps(u_lane, _mm_mul_ps(ev, inv_det));
    _mm_store_ps(v_lane, _mm_mul_ps(ew, inv_det));
    for (; lanes; lanes &= lanes - 1) {
      const int lane = __builtin_ctz(static_cast<unsigned>(lanes));
      if (t_lane[lane] < hit.t) {
        hit.t = t_lane[lane];
        hit.prim_id = tri.prim_id[lane];
        hit.u = u_lane[lane];
        hit.v = v_lane[lane];
        updated = true;
      }
    }
  }
  for (int rest = on_edge; rest; rest &= rest - 1) {
    const int lane = __builtin_ctz(static_cast<unsigned>(rest));
    const Vec3 v0{tri.vertex[0][0][lane], tri.vertex[0][1][lane], tri.vertex[0][2][lane]};
    const Vec3 v1{tri.vertex[1][0][lane], tri.vertex[1][1][lane], tri.vertex[1][2][lane]};
    const Vec3 v2{tri.vertex[2][0][lane], tri.vertex[2][1][lane], tri.vertex[2][2][lane]};
    updated |= intersect_triangle(scalar_ray, v0, v1, v2, tri.prim_id[lane], hit);
  }
  return updated;
}

}  // namespace rayaccel::wide
