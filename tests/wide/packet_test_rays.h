// What the packet tests of bvh_wide share: the variants they run (the best instruction set, AVX2 alone, and four-wide
// nodes, traced one by one) and camera rays in the tile order packets are meant for.
#pragma once

#include <vector>

#include "rayaccel/render/camera.h"
#include "rayaccel/render/workloads.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel::wide {

inline constexpr const char* kPacketSpecs[] = {"bvh_wide", "bvh_wide:width=8,isa=avx2", "bvh_wide:width=4"};

/// Camera rays of a framing camera in 4 x 2 pixel tiles, the order packets are meant for.
inline std::vector<Ray> tiled_camera_rays(const Scene& scene, int width, int height) {
  const std::vector<Ray> rows = primary_rays(Camera::framing(scene.bounds()), width, height);
  std::vector<Ray> tiled;
  for (std::size_t i : packet_tile_order(width, height)) tiled.push_back(rows[i]);
  return tiled;
}

}  // namespace rayaccel::wide
