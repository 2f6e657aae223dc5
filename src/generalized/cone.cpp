// Cone checks, the cone/ball and cone/box tests and the direction pattern.
#include "rayaccel/generalized/cone.h"

#include <cmath>
#include <numbers>
#include <string>

#include "rayaccel/core/error.h"

namespace rayaccel::generalized {

namespace {

using detail::dcross;
using detail::ddot;

DVec3 unit(const DVec3& v) {
  const double n = dnorm(v);
  return {v.x / n, v.y / n, v.z / n};
}

}  // namespace

PreparedCone::PreparedCone(const Cone& cone) : cone_(cone) {
  if (!is_finite(cone.apex)) throw Error("cone: apex is not finite");
  const DVec3 a = to_d(cone.axis);
  if (!is_finite(cone.axis) || dnorm(a) == 0.0) throw Error("cone: axis is zero or not finite");
  if (!(cone.half_angle > 0.0f && cone.half_angle < std::numbers::pi_v<float> / 2.0f)) {
    throw Error("cone: half_angle " + std::to_string(cone.half_angle) + " is not in (0, pi/2)");
  }
  if (!(cone.t_min >= 0.0f && cone.t_min <= cone.t_max)) {
    throw Error("cone: t range [" + std::to_string(cone.t_min) + ", " + std::to_string(cone.t_max) +
                "] is not a range of distances >= 0");
  }
  axis_ = unit(a);
  const DVec3 helper = std::fabs(axis_.x) < 0.5 ? DVec3{1, 0, 0} : DVec3{0, 1, 0};
  const DVec3 u = unit(dcross(axis_, helper));
  const DVec3 v = dcross(axis_, u);
  u_ = u;
  v_ = v;
  // Square pyramid around the cone: its corners at tan(angle) * sqrt(2) * (1 + 1e-6) off the axis at distance 1.
  const double r = std::tan(double(cone.half_angle)) * (1.0 + 1e-6);
  DVec3 edges[4];
  const double su[4] = {1, -1, -1, 1}, sv[4] = {1, 1, -1, -1};
  for (int i = 0; i < 4; ++i) {
    edges[i] = {axis_.x + r * (su[i] * u.x + sv[i] * v.x), axis_.y + r * (su[i] * u.y + sv[i] * v.y),
                axis_.z + r * (su[i] * u.z + sv[i] * v.z)};
  }
  pyramid_ = Beam::through(cone.apex, edges, 4);
}

bool PreparedCone::sphere_outside(const Vec3& center, float radius) const {
  if (!(radius >= 0.0f)) return true;
  if (!std::isfinite(radius) || !is_finite(center)) return false;
  const DVec3 c{double(center.x) - cone_.apex.x, double(center.y) - cone_.apex.y, double(center.z) - cone_.apex.z};
  const double d = dnorm(c), r = radius;
  const double slack = 1e-9 * (d + r);
  if (d - r > double(cone_.t_max) + slack) return true;  // every point farther than t_max
  if (d + r < double(cone_.t_min) - slack) return true;  // every point nearer than t_min
  if (d <= r + slack) return false;                      // the apex is in the ball
  // Angle between the center's direction and the axis against the half-angle widened by the ball's angular radius.
  const double along = ddot(c, axis_);
  const double across = dnorm(dcross(c, axis_));
  const double angle = std::atan2(across, along);
  const double reach = double(cone_.half_angle) + std::asin(std::fmin(1.0, r / d));
  return angle > reach + 1e-9;
}

bool PreparedCone::box_outside(const AABB& box, float slack) const {
  if (box.is_empty()) return true;
  if (pyramid_.box_outside(box, slack)) return true;
  // The ball around the float center: the extent's half plus the rounding of the center and of the length.
  const Vec3 half = box.extent() * 0.5f;
  const float magnitude = max_component(max(abs(box.lo), abs(box.hi)));
  const float radius = (length(half) + slack * 1.75f + magnitude * 0x1p-20f) * (1.0f + 0x1p-20f);
  return sphere_outside(box.center(), radius);
}

bool PreparedCone::triangle_outside(const Vec3& a, const Vec3& b, const Vec3& c) const {
  if (pyramid_.triangle_outside(a, b, c)) return true;
  AABB box;
  box.extend(a).extend(b).extend(c);
  return box_outside(box, 0.0f);
}

std::vector<Vec3> PreparedCone::pattern(int count) const {
  std::vector<Vec3> out;
  if (count <= 0) return out;
  out.reserve(std::size_t(count));
  const double golden = (3.0 - std::sqrt(5.0)) / 2.0;  // the golden angle as a fraction of a turn
  for (int k = 0; k < count; ++k) {
    const double turn = golden * k;
    out.push_back(cone_direction(cone_.axis, cone_.half_angle, (k + 0.5) / count, turn - std::floor(turn)));
  }
  return out;
}

Vec3 cone_direction(const Vec3& axis, double half_angle, double s, double t) {
  const DVec3 a = unit(to_d(axis));
  const DVec3 helper = std::fabs(a.x) < 0.5 ? DVec3{1, 0, 0} : DVec3{0, 1, 0};
  const DVec3 u = unit(dcross(a, helper));
  const DVec3 v = dcross(a, u);
  const double cos_b = 1.0 - s * (1.0 - std::cos(half_angle));
  const double sin_b = std::sqrt(std::fmax(0.0, 1.0 - cos_b * cos_b));
  const double psi = 2.0 * std::numbers::pi * t;
  const double cu = sin_b * std::cos(psi), cv = sin_b * std::sin(psi);
  return Vec3{float(cos_b * a.x + cu * u.x + cv * v.x), float(cos_b * a.y + cu * u.y + cv * v.y),
              float(cos_b * a.z + cu * u.z + cv * v.z)};
}

}  // namespace rayaccel::generalized
