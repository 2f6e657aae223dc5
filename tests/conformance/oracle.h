// The brute-force oracle check every conformance test uses: build a registered structure, then compare its
// closest hits and any-hit answers ray by ray with BruteForce's, allowing only genuine ties in t.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel::conformance {

/// Relative tolerance on the closest-hit t. Every structure and the oracle run the same kernel on the same
/// PreparedRay, so a hit on the same primitive has a bit-identical t, u and v; the tolerance (about 8 ulps) only
/// admits a structure that re-derives ray constants in another rounding order, and is far below any gap between
/// distinct surfaces along a ray that the scenes make, so a wrong primitive is not hidden by it. When the primitives
/// differ, the t values must tie exactly (see hit_mismatch()).
inline constexpr float kRelativeTTolerance = 1e-6f;
/// Absolute tolerance on u and v of a hit on the same primitive (same reasoning; u, v lie in [0, 1]).
inline constexpr float kBarycentricTolerance = 1e-6f;

/// Every spec accelerator_variant_names() lists: the parameter set of every conformance suite.
const std::vector<std::string>& variant_specs();
/// A valid gtest name for a spec ("bvh:bv=obb,builder=ploc" -> "bvh_bv_obb_builder_ploc"); a name that two specs
/// would share gets the spec's index appended.
std::string spec_test_name(const ::testing::TestParamInfo<std::string>& info);

/// The fixture of every conformance suite; GetParam() is the structure's spec.
class ConformanceTest : public ::testing::TestWithParam<std::string> {};

/// make_accelerator(spec), then build(scene); adds a test failure for each problem validate() reports.
std::unique_ptr<Accelerator> build_checked(const std::string& spec, const Scene& scene);

/// Closest hits of brute force, the reference answers (the last few are remembered, keyed by the whole scene and
/// rays: every variant of a test asks for the same ones).
std::vector<Hit> brute_force_hits(const Scene& scene, std::span<const Ray> rays);

/// Empty when `actual` is a correct closest hit given the oracle's `expected`, else a description of the fault:
/// found must agree; t within kRelativeTTolerance; same prim_id with the same u, v, or a different prim_id only
/// when the kernel, re-run on that primitive, hits it at exactly the oracle's t (a tie).
std::string hit_mismatch(const Scene& scene, const Ray& ray, const Hit& expected, const Hit& actual);

/// Ray and hit in round-trip precision, for failure messages.
std::string describe(const Ray& ray);
std::string describe(const Hit& hit);

/// Checks the single-ray intersect() and occluded() and the packet batches intersect_packets() and occluded_packets()
/// of every ray against `reference` (brute force's closest hits: occluded must equal found). Reports the first few
/// faults in detail and the total count, labelled.
void expect_matches_reference(const Accelerator& accel, const Scene& scene, std::span<const Ray> rays,
                              std::span<const Hit> reference, const std::string& label);
/// The same, with the reference computed here.
void expect_matches_brute_force(const Accelerator& accel, const Scene& scene, std::span<const Ray> rays,
                                const std::string& label);

}  // namespace rayaccel::conformance
