// Rays as users with telephoto cameras, lidar far from its target and unnormalized directions make them: aimed at
// points of a mesh's triangles (interior points, points on edges, vertices) from 1 to 1e6 scene sizes away, with
// direction lengths from 1e-6 to 1e6, some starting part-way (t_min > 0) or ending past the target (finite t_max);
// and the check of a structure's answers to them against the exact reference.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "exact_reference.h"
#include "rayaccel/accel/accelerator.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel::exact {

inline const std::vector<float> kSceneSizesAway = {1.0f, 10.0f, 1e2f, 1e3f, 1e4f, 1e5f, 1e6f};
inline const std::vector<float> kDirectionLengths = {1e-6f, 1e-3f, 1.0f, 1e3f, 1e6f};

/// `per_combination` rays for every distance in `distances` (in scene sizes: the mesh box's diagonal) and direction
/// length in `lengths`, seeded.
std::vector<Ray> far_rays(const TriangleMesh& mesh, const std::vector<float>& distances,
                          const std::vector<float>& lengths, int per_combination, std::uint64_t seed);

/// The exact hits of every ray (ExactReference::hits_past_t_min).
std::vector<std::vector<ExactHit>> exact_hits(const ExactReference& reference, const std::vector<Ray>& rays);

/// Checks accel.intersect() and accel.occluded() on every ray against the exact hits; reports the first few faults
/// and the count, labelled. Returns the number of faults.
std::size_t expect_exact_answers(const Accelerator& accel, const std::vector<Ray>& rays,
                                 const std::vector<std::vector<ExactHit>>& exact, const std::string& label);

}  // namespace rayaccel::exact
