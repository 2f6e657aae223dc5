// Signed distance: closest points and parity votes, combined point by point.
#include "rayaccel/query/signed_distance.h"

#include <cstdint>
#include <string>
#include <vector>

#include "rayaccel/core/error.h"

namespace rayaccel {

void signed_distances(const Accelerator& accel, std::span<const Vec3> points, std::span<float> distance,
                      std::span<ClosestPoint> closest, const ParityInsideConfig& config) {
  if (distance.size() != points.size() || (!closest.empty() && closest.size() != points.size())) {
    throw Error("signed distance: " + std::to_string(points.size()) + " points but " +
                std::to_string(distance.size()) + " distance and " + std::to_string(closest.size()) +
                " closest-point slots");
  }
  std::vector<std::uint8_t> inside(points.size());
  inside_by_parity(accel, points, inside, config);
  std::vector<ClosestPoint> own;
  if (closest.empty()) {
    own.resize(points.size());
    closest = own;
  }
  accel.closest_points(points, closest);
  for (std::size_t i = 0; i < points.size(); ++i) distance[i] = inside[i] ? -closest[i].distance : closest[i].distance;
}

}  // namespace rayaccel
