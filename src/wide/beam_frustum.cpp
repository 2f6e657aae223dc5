// The float frustum of a beam: side planes through its corner rays, axis planes where every ray points one way, and
// the exact proof that a ray lies on the inner side of every plane (beam_frustum.h).
#include "rayaccel/wide/beam_frustum.h"

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

}  // namespace rayaccel::wide
