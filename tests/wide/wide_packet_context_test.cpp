// bvh_wide's packet traversal under a query context (intersect_packets / occluded_packets with a QueryContext): on
// coherent camera rays (its fast path, each lane's rules asked before every triangle test) the answers of the
// single-ray context queries, for a skipped primitive per ray, ray and geometry masks, primitive switches, a filter
// and all of them at once, on every width and instruction set. The conformance suite checks the packet forms of
// every structure on incoherent rays.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include "packet_test_rays.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/core/query_context.h"
#include "rayaccel/scene/builtin_scenes.h"

namespace rayaccel::wide {
namespace {

/// The packet forms under `context` against its single-ray forms: the same t bit for bit (the primitive may differ
/// only at a tie in t), a primitive the context allows, the same occlusion. Returns the rays that hit.
int expect_context_packets_match(const Accelerator& accel, const QueryContext& context, const std::vector<Ray>& rays,
                                 const std::string& what) {
  std::vector<Hit> packets(rays.size());
  accel.intersect_packets(context, rays, packets);
  std::vector<std::uint8_t> occluded(rays.size(), 2);
  accel.occluded_packets(context, rays, occluded);
  int hits = 0, faults = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hit single = accel.intersect(context, rays[i], i);
    const Hit& p = packets[i];
    hits += single.found() ? 1 : 0;
    NoStats none;
    const ContextStats<NoStats> rules(context, i, none);
    std::string fault;
    if (std::bit_cast<std::uint32_t>(p.t) != std::bit_cast<std::uint32_t>(single.t)) fault = "t differs";
    if (fault.empty() && p.prim_id == single.prim_id && (p.u != single.u || p.v != single.v)) fault = "u, v differ";
    if (fault.empty() && p.found() && !rules.allows(p.prim_id)) fault = "hit a primitive the context rules out";
    if (fault.empty() && occluded[i] != (accel.occluded(context, rays[i], i) ? 1 : 0)) fault = "occlusion differs";
    if (!fault.empty() && ++faults <= 5) {
      ADD_FAILURE() << accel.spec() << " / " << what << " ray " << i << " (packet " << i / 8 << "): " << fault
                    << "; packet hit " << p.prim_id << " at " << p.t << ", single ray " << single.prim_id << " at "
                    << single.t;
    }
  }
  EXPECT_EQ(faults, 0) << accel.spec() << " / " << what;
  return hits;
}

TEST(WidePacketContext, CoherentRaysUnderEveryRuleMatchSingleRays) {
  for (const char* scene_name : {"default", "teapot_stadium"}) {
    const Scene scene = make_builtin_scene(scene_name);
    const std::vector<Ray> rays = tiled_camera_rays(scene, 45, 37);  // a last, partial packet
    const auto n = static_cast<std::uint32_t>(scene.primitive_count());
    // Three geometries of about a third each; ray masks 1, 2, 3 in turn against geometry masks 1, 2, 2.
    const std::vector<std::uint32_t> starts = {0, n / 3, 2 * n / 3};
    const std::vector<std::uint32_t> geometry_masks = {1, 2, 2};
    std::vector<std::uint32_t> ray_masks(rays.size()), skip(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) ray_masks[i] = static_cast<std::uint32_t>(i % 3 + 1);
    std::vector<std::uint8_t> enabled(n);
    for (std::uint32_t p = 0; p < n; ++p) enabled[p] = (p * 2654435761u >> 13) % 4 != 0;
    int filtered = 0;
    auto reject_fifths = [&](const HitCandidate& c) {
      if (c.ray_index >= rays.size()) ++filtered;  // a bad index is counted and fails below
      return c.prim_id % 5 != 0;
    };
    for (const char* spec : kPacketSpecs) {
      auto accel = make_accelerator(spec);
      accel->build(scene);
      std::vector<Hit> first(rays.size());
      accel->intersect(rays, first);
      for (std::size_t i = 0; i < rays.size(); ++i) skip[i] = first[i].prim_id;
      const std::string label = std::string(scene_name) + " / ";

      QueryContext skipping;
      skipping.skip_primitive = skip;
      const int behind = expect_context_packets_match(*accel, skipping, rays, label + "skip");
      const auto skipped = std::count_if(first.begin(), first.end(), [](const Hit& h) { return h.found(); });
      EXPECT_GT(skipped, static_cast<long>(rays.size()) / 10) << spec << " / " << scene_name;  // real skips
      EXPECT_GT(behind, 0) << spec << " / " << scene_name << ": no ray hits anything behind its first hit";
      QueryContext masked;
      masked.ray_mask = ray_masks;
      masked.geometry_starts = starts;
      masked.geometry_mask = geometry_masks;
      expect_context_packets_match(*accel, masked, rays, label + "masks");
      QueryContext switched;
      switched.primitive_enabled = enabled;
      expect_context_packets_match(*accel, switched, rays, label + "switches");
      QueryContext filter;
      filter.set_filter(reject_fifths);
      expect_context_packets_match(*accel, filter, rays, label + "filter");
      QueryContext all = masked;
      all.skip_primitive = skip;
      all.primitive_enabled = enabled;
      all.set_filter(reject_fifths);
      expect_context_packets_match(*accel, all, rays, label + "all at once");
    }
    EXPECT_EQ(filtered, 0) << "the filter saw a ray index outside the batch";
  }
}

}  // namespace
}  // namespace rayaccel::wide
