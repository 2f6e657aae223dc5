// Inside tests: crossing parity over a few fixed rays with a majority vote, and the generalised winding number by
// direct summation of solid angles (Jacobson et al. 2013; Van Oosterom & Strackee 1983 for a triangle's solid angle).
#include "rayaccel/query/inside.h"

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>

#include "rayaccel/core/error.h"

namespace rayaccel {
namespace {

void check_points(const char* query, std::span<const Vec3> points, std::size_t outputs) {
  if (outputs != points.size()) {
    throw Error(std::string(query) + ": " + std::to_string(points.size()) + " points but " + std::to_string(outputs) +
                " output slots");
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!is_finite(points[i])) {
      std::ostringstream text;
      text << query << ": point " << i << " (" << points[i].x << ", " << points[i].y << ", " << points[i].z
           << ") is not finite";
      throw Error(text.str());
    }
  }
}

/// Fixed directions of no special relation to the axes, to each other or to diagonals (their components are
/// distinct irrational-looking ratios), so that the faces of axis-aligned and grid-like models are not met edge-on.
constexpr std::array<Vec3, 7> kParityDirections = {{{0.5431f, 0.2718f, 0.7947f},
                                                     {-0.3183f, 0.8660f, -0.3852f},
                                                     {0.7071f, -0.5773f, -0.4082f},
                                                     {-0.6931f, -0.4142f, 0.5877f},
                                                     {0.1234f, -0.9017f, 0.4142f},
                                                     {-0.8414f, 0.1411f, -0.5214f},
                                                     {0.3010f, 0.4771f, -0.8257f}}};

/// Solid angle of triangle (a, b, c) seen from the origin, signed by orientation, over 4 pi.
double solid_angle_fraction(const std::array<double, 3>& a, const std::array<double, 3>& b,
                            const std::array<double, 3>& c) {
  const auto dot = [](const std::array<double, 3>& x, const std::array<double, 3>& y) {
    return x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
  };
  const double la = std::sqrt(dot(a, a)), lb = std::sqrt(dot(b, b)), lc = std::sqrt(dot(c, c));
  const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
  if (det == 0.0) return 0.0;  // the point lies in the triangle's plane (on the triangle, or beside it: no angle)
  const double denominator = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
  return 2.0 * std::atan2(det, denominator) / (4.0 * std::numbers::pi);
}

}  // namespace

void inside_by_parity(const Accelerator& accel, std::span<const Vec3> points, std::span<std::uint8_t> inside,
                      const ParityInsideConfig& config) {
  if (config.ray_count < 1 || config.ray_count > int(kParityDirections.size()) || config.ray_count % 2 == 0) {
    throw Error("inside test: ray_count " + std::to_string(config.ray_count) + " must be odd and in 1..7");
  }
  check_points("inside test", points, inside.size());
  if (!accel.supports_queries()) {
    throw Error("inside test: '" + accel.spec() + "' has no all-hits query (use brute_force, bvh or bvh_wide)");
  }
  detail::parallel_for_rays(points.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      int odd = 0;
      for (int r = 0; r < config.ray_count; ++r) {
        const Ray ray{points[i], 0.0f, kParityDirections[r], std::numeric_limits<float>::infinity()};
        odd += static_cast<int>(accel.count_hits(ray) % 2);
      }
      inside[i] = 2 * odd > config.ray_count ? 1 : 0;
    }
  });
}

void winding_numbers(const Scene& scene, std::span<const Vec3> points, std::span<double> winding) {
  if (scene.kind() != PrimitiveKind::triangles) {
    throw Error("winding numbers: '" + scene.name() + "' holds " + to_string(scene.kind()) + ", not triangles");
  }
  check_points("winding numbers", points, winding.size());
  detail::parallel_for_rays(points.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const Vec3& p = points[i];
      double sum = 0.0;
      for (std::uint32_t id = 0; id < scene.primitive_count(); ++id) {
        if (!scene.is_valid(id)) continue;
        const std::array<Vec3, 3> t = scene.triangle(id);
        std::array<std::array<double, 3>, 3> rel;
        for (int k = 0; k < 3; ++k) {
          rel[k] = {double(t[k].x) - p.x, double(t[k].y) - p.y, double(t[k].z) - p.z};
        }
        sum += solid_angle_fraction(rel[0], rel[1], rel[2]);
      }
      winding[i] = sum;
    }
  });
}

}  // namespace rayaccel
