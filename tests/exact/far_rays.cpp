// Far and short rays, and their check against the exact reference: see far_rays.h.
#include "far_rays.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../conformance/test_scenes.h"
#include "rayaccel/core/aabb.h"

namespace rayaccel::exact {

std::vector<Ray> far_rays(const TriangleMesh& mesh, const std::vector<float>& distances,
                          const std::vector<float>& lengths, int per_combination, std::uint64_t seed) {
  conformance::Rng rng(seed);
  AABB box;
  for (const Vec3& v : mesh.vertices) box.extend(v);
  const float size = length(box.extent());
  std::vector<Ray> rays;
  for (float distance : distances) {
    for (float dir_length : lengths) {
      for (int i = 0; i < per_combination; ++i) {
        const auto& tri = mesh.triangles[rng.below(static_cast<std::uint32_t>(mesh.triangles.size()))];
        const Vec3 a = mesh.vertices[tri[0]], b = mesh.vertices[tri[1]], c = mesh.vertices[tri[2]];
        Vec3 target;
        switch (i % 4) {
          case 0:  // a vertex
            target = a;
            break;
          case 1: {  // a point on an edge
            const float s = rng.uniform();
            target = a + (b - a) * s;
            break;
          }
          default: {  // an interior point
            float s = rng.uniform(), t = rng.uniform();
            if (s + t > 1.0f) { s = 1.0f - s; t = 1.0f - t; }
            target = a + (b - a) * s + (c - a) * t;
          }
        }
        Ray ray;
        ray.origin = target + rng.unit_vector() * (distance * size);
        const Vec3 to_target = target - ray.origin;
        const float dist = length(to_target);
        if (!(dist > 0.0f)) continue;
        ray.direction = to_target * (dir_length / dist);
        const float t_target = dist / dir_length;
        switch (rng.below(6)) {
          case 0: ray.t_min = 0.5f * t_target; break;  // starts part-way
          case 1: ray.t_max = 2.0f * t_target; break;  // ends past the target
          case 2: ray.t_max = 0.5f * t_target; break;  // ends before it
          default: break;
        }
        rays.push_back(ray);
      }
    }
  }
  return rays;
}

std::vector<std::vector<ExactHit>> exact_hits(const ExactReference& reference, const std::vector<Ray>& rays) {
  std::vector<std::vector<ExactHit>> out;
  out.reserve(rays.size());
  for (const Ray& ray : rays) out.push_back(reference.hits_past_t_min(ray));
  return out;
}

std::size_t expect_exact_answers(const Accelerator& accel, const std::vector<Ray>& rays,
                                 const std::vector<std::vector<ExactHit>>& exact, const std::string& label) {
  std::size_t faults = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    std::string fault = ExactReference::closest_hit_mismatch(rays[i], exact[i], accel.intersect(rays[i]));
    if (fault.empty()) fault = ExactReference::occlusion_mismatch(rays[i], exact[i], accel.occluded(rays[i]));
    if (fault.empty()) continue;
    if (++faults <= 5) ADD_FAILURE() << label << ", ray " << i << ": " << fault;
  }
  EXPECT_EQ(faults, 0u) << label << ": " << faults << " of " << rays.size() << " rays disagree with exact arithmetic";
  return faults;
}

}  // namespace rayaccel::exact
