// Exact domain: see exact_domain.h.
#include "exact_domain.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

namespace rayaccel::exact {
namespace {

constexpr double kLargest = 0x1p126;   // half of float's range: A_x - s A_z with |s| <= 1 stays below FLT_MAX
constexpr double kSmallest = 0x1p-100;  // 2^-18 of it (the reference's t tolerance) is still a normal float

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// The README's void rays: NaN or infinite origin or direction, no direction left, a NaN bound or t_max < t_min.
bool is_void(const Ray& read) {
  const Vec3& d = read.direction;
  return !finite(read.origin) || !finite(d) || (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f) ||
         std::isnan(read.t_min) || std::isnan(read.t_max) || !(read.t_min <= read.t_max);
}

}  // namespace

const char* to_string(DomainVerdict verdict) {
  switch (verdict) {
    case DomainVerdict::inside: return "inside";
    case DomainVerdict::coordinate_out_of_range: return "coordinate out of range";
    case DomainVerdict::depth_out_of_range: return "depth out of range";
  }
  return "?";
}

Ray ray_as_read(const Ray& ray) {
  Ray read = ray;
  for (float* d : {&read.direction.x, &read.direction.y, &read.direction.z}) {
    if (std::fabs(*d) < std::numeric_limits<float>::min()) *d = std::copysign(0.0f, *d);
  }
  return read;
}

DomainVerdict exact_domain(const Ray& ray, const TriangleMesh& mesh) {
  const Ray read = ray_as_read(ray);
  if (is_void(read)) return DomainVerdict::inside;
  const std::array<double, 3> o{read.origin.x, read.origin.y, read.origin.z};
  const std::array<double, 3> d{std::fabs(double(read.direction.x)), std::fabs(double(read.direction.y)),
                                std::fabs(double(read.direction.z))};
  const double d_max = std::fmax(d[0], std::fmax(d[1], d[2]));
  for (const auto& triangle : mesh.triangles) {
    const Vec3 v[3] = {mesh.vertices[triangle[0]], mesh.vertices[triangle[1]], mesh.vertices[triangle[2]]};
    if (!finite(v[0]) || !finite(v[1]) || !finite(v[2])) continue;  // never hit
    for (const Vec3& vertex : v) {
      for (std::size_t k = 0; k < 3; ++k) {
        const double a = std::fabs(double(vertex[k]) - o[k]);
        if (a > kLargest) return DomainVerdict::coordinate_out_of_range;
        if (d[k] != d_max) continue;  // not a dominant axis: no depth along it
        const double depth = a / d_max;
        if (depth != 0.0 && (depth < kSmallest || depth > kLargest)) return DomainVerdict::depth_out_of_range;
      }
    }
  }
  return DomainVerdict::inside;
}

}  // namespace rayaccel::exact
