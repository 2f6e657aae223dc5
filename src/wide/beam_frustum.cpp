// The float frustum of a beam: side planes through its corner rays, axis planes where every ray points one way, and
// the exact proof that a ray lies on the inner side of every plane (beam_frustum.h).
#include "rayaccel/wide/beam_frustum.h"

#include <emmintrin.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rayaccel::wide {

namespace {

/// x rounded to a float no smaller than x.
float round_up(double x) {
  const float f = float(x);
  return double(f) >= x ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
}

}  // namespace

BeamFrustum BeamFrustum::through(const Vec3& a, const Vec3 corners[4]) {
  BeamFrustum f;
  f.apex = a;
  if (!is_finite(a)) return f;
  for (int i = 0; i < 4; ++i) {
    if (!is_finite(corners[i])) return f;
  }
  f.apex_magnitude = std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)});
  double mean[3] = {0, 0, 0};
  for (int i = 0; i < 4; ++i) {
    for (int k = 0; k < 3; ++k) mean[k] += double(corners[i][k]);
  }
  int count = 0;
  const auto add_plane = [&](const double n[3]) {
    for (int k = 0; k < 3; ++k) f.normal[count][k] = float(n[k]);  // any float normal: holds() checks the rays
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
      sum += std::fabs(double(f.normal[count][k]));
      f.far_is_hi[count][k] = f.normal[count][k] >= 0.0f;
    }
    f.margin[count] = round_up(sum * double(kMarginScale));
    ++count;
  };
  for (int i = 0; i < 4; ++i) {
    const Vec3& p = corners[i];
    const Vec3& q = corners[(i + 1) % 4];
    double n[3] = {double(p.y) * q.z - double(p.z) * q.y, double(p.z) * q.x - double(p.x) * q.z,
                   double(p.x) * q.y - double(p.y) * q.x};
    if (n[0] * mean[0] + n[1] * mean[1] + n[2] * mean[2] < 0.0) {
      for (double& x : n) x = -x;
    }
    add_plane(n);
  }
  for (int k = 0; k < 3; ++k) {
    bool positive = true, negative = true;
    for (int i = 0; i < 4; ++i) {
      positive = positive && corners[i][k] > 0.0f;
      negative = negative && corners[i][k] < 0.0f;
    }
    if (positive || negative) {
      double n[3] = {0, 0, 0};
      n[k] = positive ? 1.0 : -1.0;
      add_plane(n);
    }
  }
  f.plane_count = count;
  return f;
}

bool BeamFrustum::holds(const Ray& ray) const {
  if (!valid() || !(ray.origin == apex) || !(ray.t_min >= 0.0f)) return false;
  const Vec3 direction = readable_direction(ray.direction);
  for (int p = 0; p < plane_count; ++p) {
    double value = 0.0, scale = 0.0;
    for (int k = 0; k < 3; ++k) {
      // The direction as PreparedRay reads it; each product exact (24 + 24 bits).
      const double term = double(normal[p][k]) * double(direction[k]);
      value += term;
      scale += std::fabs(term);
    }
    if (!(value > scale * 0x1p-50)) return false;
  }
  return true;
}

bool BeamFrustum::box_outside(const AABB& box) const {
  if (!valid()) return false;
  if (!(box.lo.x <= box.hi.x)) return true;  // empty
  // As frustum_child_lanes(): the box grown by its slack and moved to the apex, its reach, then each plane's
  // farthest corner against the plane's margin (here four planes a pass, the unused lanes culling nothing).
  float magnitude = apex_magnitude;
  for (int k = 0; k < 3; ++k) magnitude = std::max(magnitude, std::max(std::fabs(box.lo[k]), std::fabs(box.hi[k])));
  const float slack = magnitude * kSlackScale;
  float lo[3], hi[3], reach = 0.0f;
  for (int k = 0; k < 3; ++k) {
    lo[k] = (box.lo[k] - slack) - apex[k];
    hi[k] = (box.hi[k] + slack) - apex[k];
    reach = std::max(reach, std::max(std::fabs(lo[k]), std::fabs(hi[k])));
  }
  const __m128 tiny = _mm_set1_ps(0x1p-126f);
  const __m128 reach4 = _mm_set1_ps(reach);
  for (int first = 0; first < plane_count; first += 4) {
    alignas(16) float n[3][4] = {}, c[3][4] = {}, m[4] = {};
    for (int i = 0; i < 4 && first + i < plane_count; ++i) {
      const int p = first + i;
      for (int k = 0; k < 3; ++k) {
        n[k][i] = normal[p][k];
        c[k][i] = far_is_hi[p][k] ? hi[k] : lo[k];
      }
      m[i] = margin[p];
    }
    __m128 v = _mm_mul_ps(_mm_load_ps(n[0]), _mm_load_ps(c[0]));
    v = _mm_add_ps(v, _mm_mul_ps(_mm_load_ps(n[1]), _mm_load_ps(c[1])));
    v = _mm_add_ps(v, _mm_mul_ps(_mm_load_ps(n[2]), _mm_load_ps(c[2])));
    const __m128 bound = _mm_add_ps(_mm_mul_ps(_mm_load_ps(m), reach4), tiny);
    const int culled = _mm_movemask_ps(_mm_cmplt_ps(_mm_add_ps(v, bound), _mm_setzero_ps()));
    if (culled & ((1 << std::min(4, plane_count - first)) - 1)) return true;
  }
  return false;
}

}  // namespace rayaccel::wide
