// The primitive test every structure's scalar leaf runs: Scene::intersect() through test_candidate(), so a query
// context (core/query_context.h) is honoured before the exact test, and plain queries compile to the test alone.
#pragma once

#include <cstdint>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/query_context.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel {

/// Counts one primitive test in `stats` and tests primitive `id` of `scene`; true when `hit` changed.
template <class Stats>
inline bool test_scene_primitive(const Scene& scene, std::uint32_t id, const PreparedRay& ray, Hit& hit,
                                 Stats& stats) {
  stats.test_primitive();
  return test_candidate(stats, id, hit, [&](Hit& h) { return scene.intersect(id, ray, h); });
}

}  // namespace rayaccel
