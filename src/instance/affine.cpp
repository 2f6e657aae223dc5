// Affine3: construction, composition, inversion (cofactors in double), and the mapping of points, boxes and rays.
#include "rayaccel/instance/affine.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/core/float_rounding.h"

namespace rayaccel {

namespace {
std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return text;
}
}  // namespace

Affine3 Affine3::translation(double x, double y, double z) { return {{1, 0, 0, x, 0, 1, 0, y, 0, 0, 1, z}}; }

Affine3 Affine3::scaling(double x, double y, double z) { return {{x, 0, 0, 0, 0, y, 0, 0, 0, 0, z, 0}}; }

Affine3 Affine3::rotation(const Vec3& axis, double radians) {
  const double x = axis.x, y = axis.y, z = axis.z;
  const double len = std::sqrt(x * x + y * y + z * z);
  if (!(len > 0.0) || !std::isfinite(len)) throw Error("rotation axis must be finite and non-zero");
  const double ux = x / len, uy = y / len, uz = z / len;
  const double c = std::cos(radians), s = std::sin(radians), k = 1.0 - c;
  Affine3 a;
  a.m = {c + ux * ux * k,      ux * uy * k - uz * s, ux * uz * k + uy * s, 0.0,
         uy * ux * k + uz * s, c + uy * uy * k,      uy * uz * k - ux * s, 0.0,
         uz * ux * k - uy * s, uz * uy * k + ux * s, c + uz * uz * k,      0.0};
  return a;
}

Affine3 Affine3::from_rows(const std::array<float, 12>& rows) {
  Affine3 a;
  for (std::size_t i = 0; i < 12; ++i) a.m[i] = rows[i];
  return a;
}

bool Affine3::is_finite() const {
  return std::all_of(m.begin(), m.end(), [](double v) { return std::isfinite(v); });
}

double Affine3::determinant() const {
  const Affine3& a = *this;
  return a(0, 0) * (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)) - a(0, 1) * (a(1, 0) * a(2, 2) - a(1, 2) * a(2, 0)) +
         a(0, 2) * (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0));
}

Affine3 Affine3::inverse() const {
  if (!is_finite()) throw Error("transform has a NaN or infinite entry");
  const Affine3& a = *this;
  double scale = 0.0;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) scale = std::max(scale, std::fabs(a(r, c)));
  }
  const double det = determinant();
  if (!(std::fabs(det) > 1e-12 * scale * scale * scale)) {
    throw Error("transform is singular (determinant " + number_text(det) + " of a linear part with largest entry " +
                number_text(scale) + "): it has no inverse");
  }
  Affine3 inv;
  inv(0, 0) = (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)) / det;
  inv(0, 1) = (a(0, 2) * a(2, 1) - a(0, 1) * a(2, 2)) / det;
  inv(0, 2) = (a(0, 1) * a(1, 2) - a(0, 2) * a(1, 1)) / det;
  inv(1, 0) = (a(1, 2) * a(2, 0) - a(1, 0) * a(2, 2)) / det;
  inv(1, 1) = (a(0, 0) * a(2, 2) - a(0, 2) * a(2, 0)) / det;
  inv(1, 2) = (a(0, 2) * a(1, 0) - a(0, 0) * a(1, 2)) / det;
  inv(2, 0) = (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0)) / det;
  inv(2, 1) = (a(0, 1) * a(2, 0) - a(0, 0) * a(2, 1)) / det;
  inv(2, 2) = (a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0)) / det;
  for (int r = 0; r < 3; ++r) {
    inv(r, 3) = -(inv(r, 0) * a(0, 3) + inv(r, 1) * a(1, 3) + inv(r, 2) * a(2, 3));
  }
  if (!inv.is_finite()) {
    throw Error("transform's inverse overflows (determinant " + number_text(det) + ")");
  }
  return inv;
}

std::array<double, 3> Affine3::apply_point(const Vec3& p) const {
  std::array<double, 3> out;
  for (int r = 0; r < 3; ++r) {
    out[static_cast<std::size_t>(r)] =
        (*this)(r, 0) * p.x + (*this)(r, 1) * p.y + (*this)(r, 2) * p.z + (*this)(r, 3);
  }
  return out;
}

std::array<double, 3> Affine3::apply_vector(const Vec3& v) const {
  std::array<double, 3> out;
  for (int r = 0; r < 3; ++r) {
    out[static_cast<std::size_t>(r)] = (*this)(r, 0) * v.x + (*this)(r, 1) * v.y + (*this)(r, 2) * v.z;
  }
  return out;
}

Affine3 operator*(const Affine3& a, const Affine3& b) {
  Affine3 out;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      double sum = c == 3 ? a(r, 3) : 0.0;
      for (int k = 0; k < 3; ++k) sum += a(r, k) * b(k, c);
      out(r, c) = sum;
    }
  }
  return out;
}

Vec3 round_to_float(const std::array<double, 3>& p) {
  return {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
}

AABB transform_box(const Affine3& transform, const AABB& box) {
  if (box.is_empty()) return box;
  std::array<double, 3> lo{INFINITY, INFINITY, INFINITY};
  std::array<double, 3> hi{-INFINITY, -INFINITY, -INFINITY};
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p{(corner & 1) ? box.hi.x : box.lo.x, (corner & 2) ? box.hi.y : box.lo.y,
                 (corner & 4) ? box.hi.z : box.lo.z};
    const std::array<double, 3> q = transform.apply_point(p);
    for (std::size_t a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], q[a]);
      hi[a] = std::max(hi[a], q[a]);
    }
  }
  // The double sums carry a rounding error far below a float ulp; the extra ulp covers it.
  AABB out;
  for (std::size_t a = 0; a < 3; ++a) {
    out.lo[a] = next_float_down(round_down_to_float(lo[a]));
    out.hi[a] = next_float_up(round_up_to_float(hi[a]));
  }
  return out;
}

Ray transform_ray(const Affine3& world_to_object, const Ray& ray) {
  Ray out = ray;
  out.origin = round_to_float(world_to_object.apply_point(ray.origin));
  out.direction = round_to_float(world_to_object.apply_vector(ray.direction));
  return out;
}

}  // namespace rayaccel
