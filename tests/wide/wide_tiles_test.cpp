// The traversals beams use over bvh_wide: intersect_tile_from() (the eight 4 x 2 packets of an 8 x 8 pixel tile under
// the tile's frustum) and intersect_packet_from() (one packet from a given node). Every ray they do not name as
// possibly tied must get intersect()'s hit bit for bit (primitive, t, u, v), a named one at least the same t; with the
// lanes proven inside the frustum by the traversal or before it; and a packet with a ray outside the frustum must be
// refused (left to the caller). For every instruction set of the eight-wide nodes this CPU runs.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include "packet_test_rays.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/render/camera.h"
#include "rayaccel/scene/builtin_scenes.h"
#include "rayaccel/wide/beam_frustum.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel::wide {
namespace {

bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }

/// The 64 rays of the 8 x 8 tile at (x0, y0) in packet order (eight 4 x 2 packets, rows of packets top to bottom).
std::vector<Ray> tile_rays(const CameraFrame& frame, int x0, int y0) {
  std::vector<Ray> rays;
  for (int py = y0; py < y0 + 8; py += 2) {
    for (int px = x0; px < x0 + 8; px += 4) {
      for (int dy = 0; dy < 2; ++dy) {
        for (int dx = 0; dx < 4; ++dx) rays.push_back(frame.ray(px + dx, py + dy));
      }
    }
  }
  return rays;
}

BeamFrustum tile_frustum(const CameraFrame& frame, int x0, int y0) {
  const Vec3 corners[4] = {frame.ray_at(float(x0), float(y0)).direction,
                           frame.ray_at(float(x0 + 8), float(y0)).direction,
                           frame.ray_at(float(x0 + 8), float(y0 + 8)).direction,
                           frame.ray_at(float(x0), float(y0 + 8)).direction};
  return BeamFrustum::through(frame.eye, corners);
}

/// Counts the rays whose hit breaks the rule above; names the first few.
int faults(const Accelerator& accel, const std::vector<Ray>& rays, const Hit* hits, std::uint64_t named,
           const std::string& what) {
  int count = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hit want = accel.intersect(rays[i]);
    const Hit& got = hits[i];
    const bool same = (named >> i & 1) ? same_bits(got.t, want.t)
                                       : got.prim_id == want.prim_id && same_bits(got.t, want.t) &&
                                             same_bits(got.u, want.u) && same_bits(got.v, want.v);
    if (!same && ++count <= 3) {
      ADD_FAILURE() << accel.spec() << " / " << what << " ray " << i << ": got prim " << got.prim_id << " at "
                    << got.t << ", intersect() prim " << want.prim_id << " at " << want.t;
    }
  }
  return count;
}

TEST(WideTiles, EveryRayNotNamedGetsIntersectsHit) {
  int tiles = 0, hits = 0, refused_packets = 0;
  for (const char* scene_name : {"default", "soup", "teapot_stadium"}) {
    const Scene scene = make_builtin_scene(scene_name);
    const CameraFrame frame = Camera::framing(scene.bounds()).frame(64, 64);
    for (const char* spec : kPacketSpecs) {
      auto accel = make_accelerator(spec);
      accel->build(scene);
      const auto* bvh = dynamic_cast<const WideBvh*>(accel.get());
      ASSERT_NE(bvh, nullptr);
      if (!bvh->has_packet_traversal()) continue;  // four-wide nodes, or a build without the eight-lane kernels
      for (int y0 = 0; y0 < 64; y0 += 8) {
        for (int x0 = 0; x0 < 64; x0 += 8) {
          const std::vector<Ray> rays = tile_rays(frame, x0, y0);
          const BeamFrustum frustum = tile_frustum(frame, x0, y0);
          ASSERT_TRUE(frustum.valid());
          for (const Ray& r : rays) ASSERT_TRUE(frustum.holds(r));
          const std::string where = std::string(scene_name) + " tile " + std::to_string(x0) + "," +
                                    std::to_string(y0);
          // A refused packet (off the packet kernels' fast path: rays of different axes kx, ky, kz, as near the
          // framing camera's diagonals) is traced here alone, as the beams do.
          Hit out[64];
          std::uint64_t packet_named = 0;
          for (int p = 0; p < 8; ++p) {
            packet_named |= std::uint64_t(unsigned(bvh->intersect_packet_from(bvh->root(), rays.data() + 8 * p, 8,
                                                                              out + 8 * p)))
                            << (8 * p);
          }
          EXPECT_EQ(faults(*accel, rays, out, packet_named, where + " packets"), 0);
          for (const bool prove : {true, false}) {
            Hit tile_hits[64];
            std::uint64_t named = 0;
            const int refused =
                bvh->intersect_tile_from(bvh->root(), frustum, rays.data(), 64, tile_hits, named, prove);
            for (int p = 0; p < 8; ++p) {
              if (!(refused >> p & 1)) continue;
              ++refused_packets;
              for (int i = 8 * p; i < 8 * p + 8; ++i) tile_hits[i] = out[i];
              named |= packet_named & (std::uint64_t(0xff) << (8 * p));
            }
            EXPECT_EQ(faults(*accel, rays, tile_hits, named, where + (prove ? " proving" : " proven")), 0);
          }
          for (const Hit& h : out) hits += h.found() ? 1 : 0;
          ++tiles;
        }
      }
    }
  }
  if (tiles == 0) GTEST_SKIP() << "no eight-lane kernels on this build";
  EXPECT_GT(hits, tiles * 8);  // the tiles hit something: the comparisons above are not of misses only
  EXPECT_LT(refused_packets, tiles * 2 * 8 / 4);  // most packets went through the tile traversal
}

TEST(WideTiles, RefusesRaysNotProvenInsideTheFrustum) {
  const Scene scene = make_builtin_scene("default");
  auto accel = make_accelerator("bvh_wide");
  accel->build(scene);
  const auto* bvh = dynamic_cast<const WideBvh*>(accel.get());
  ASSERT_NE(bvh, nullptr);
  if (!bvh->has_packet_traversal()) GTEST_SKIP() << "no eight-lane kernels on this build";
  const CameraFrame frame = Camera::framing(scene.bounds()).frame(64, 64);
  const BeamFrustum frustum = tile_frustum(frame, 0, 0);
  std::vector<Ray> rays = tile_rays(frame, 0, 0);
  Hit out[64];
  std::uint64_t named = 0;
  const int refused_as_made = bvh->intersect_tile_from(bvh->root(), frustum, rays.data(), 64, out, named, true);
  EXPECT_EQ(refused_as_made & (1 << 4), 0);  // the packet changed below joins as made
  rays[37] = frame.ray(40, 40);              // one ray of packet 4 from another tile
  EXPECT_EQ(bvh->intersect_tile_from(bvh->root(), frustum, rays.data(), 64, out, named, true),
            refused_as_made | (1 << 4));
  EXPECT_THROW(bvh->intersect_tile_from(bvh->root(), frustum, rays.data(), 60, out, named, true), Error);
}

}  // namespace
}  // namespace rayaccel::wide
