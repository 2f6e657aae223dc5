// libFuzzer target: a differential test of every registered structure variant against brute force on a small
// fuzzed scene. The input's bytes become up to 12 triangles and 8 rays; each coordinate byte picks a value from a
// table of hostile floats (0, -0, subnormals, 1e-30, 1, huge, FLT_MAX, Inf, NaN) or a raw float, so NaN, Inf,
// subnormal, huge and duplicate vertices are common. Brute force's answers (closest hit and occlusion) must be what
// the exact reference (tests/exact: GMP rationals on the float inputs, no code shared with the kernels) allows, for
// every ray inside the domain the library guarantees (tests/exact/exact_domain.h). Every structure's answers must
// match brute force's as in the conformance suite (same found/occluded, the same t, a different primitive only at
// exactly the same t) or, inside the exact domain, be what the exact reference allows too: the library's rule lets
// either of two hits within their t error bounds be returned. Outside the domain a different primitive may lie a
// few ulps of t from brute force's (brute_force_fault()). Rays outside it are counted, and the counts printed when
// the run ends.
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "exact_domain.h"
#include "exact_reference.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"

namespace {

using namespace rayaccel;

/// Reads the input front to back; zeros once it runs out.
class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  float raw_float() {
    std::uint32_t bits = 0;
    for (int i = 0; i < 4; ++i) bits = (bits << 8) | byte();
    return std::bit_cast<float>(bits);
  }
  /// A hostile value, or a raw float for codes past the table.
  float value() {
    static const float kTable[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, 2.0f, 1e-30f, -1e-30f, 1e-40f, -1e-45f,
                                   1e30f, -1e30f, 2e38f, -2e38f, std::numeric_limits<float>::max(),
                                   -std::numeric_limits<float>::max(), std::numeric_limits<float>::infinity(),
                                   std::numeric_limits<float>::quiet_NaN(), 3.0f, 0.25f};
    constexpr std::uint8_t kCount = sizeof(kTable) / sizeof(kTable[0]);
    const std::uint8_t code = byte();
    if (code < kCount) return kTable[code];
    if (code < 128) return float(code - kCount) * 0.125f - 4.0f;  // small grid values: shared edges, duplicates
    return raw_float();
  }
  bool done() const { return pos_ >= size_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

/// The scene of the input being run, for the report of a disagreement.
const TriangleMesh* current_mesh = nullptr;

/// Stops the run on a disagreement, printing what disagreed first so that a CI log names it, and the scene.
[[noreturn]] void disagree(const char* what, const std::string& spec, const Ray* ray, const Hit* got, const Hit* want) {
  std::fprintf(stderr, "fuzz_differential: %s: %s\n", spec.c_str(), what);
  for (std::size_t i = 0; current_mesh && i < current_mesh->triangles.size(); ++i) {
    std::fprintf(stderr, "  prim %zu:", i);
    for (const std::uint32_t v : current_mesh->triangles[i]) {
      const Vec3& p = current_mesh->vertices[v];
      std::fprintf(stderr, " (%a, %a, %a)", p.x, p.y, p.z);
    }
    std::fprintf(stderr, "\n");
  }
  if (ray) {
    std::fprintf(stderr, "  ray origin (%a, %a, %a) direction (%a, %a, %a) t (%a, %a]\n", ray->origin.x, ray->origin.y,
                 ray->origin.z, ray->direction.x, ray->direction.y, ray->direction.z, ray->t_min, ray->t_max);
  }
  if (got) std::fprintf(stderr, "  got prim %u t %a\n", unsigned(got->prim_id), got->t);
  if (want) std::fprintf(stderr, "  brute force prim %u t %a\n", unsigned(want->prim_id), want->t);
  __builtin_trap();
}

/// How many rays were checked against the exact reference, and how many were left out, by DomainVerdict.
struct ExactCounts {
  std::uint64_t by_verdict[3] = {};
  ~ExactCounts() {  // printed when the run ends (libFuzzer ends with exit())
    using exact::DomainVerdict;
    std::uint64_t total = 0;
    for (const std::uint64_t n : by_verdict) total += n;
    std::fprintf(stderr, "fuzz_differential: %llu of %llu rays checked against the exact reference; skipped:",
                 (unsigned long long)by_verdict[0], (unsigned long long)total);
    for (const DomainVerdict v : {DomainVerdict::coordinate_out_of_range, DomainVerdict::depth_out_of_range}) {
      std::fprintf(stderr, " %llu %s;", (unsigned long long)by_verdict[int(v)], exact::to_string(v));
    }
    std::fprintf(stderr, "\n");
  }
};
ExactCounts exact_counts;

/// The exact hits of a ray inside the exact domain (else none: the ray's answers are checked against brute force
/// only), counted by verdict.
struct ExactAnswers {
  bool inside = false;
  Ray read;                          ///< the ray as every kernel reads it
  std::vector<exact::ExactHit> hits;  ///< past t_min, sorted by t
};

ExactAnswers exact_answers(const exact::ExactReference& reference, const TriangleMesh& mesh, const Ray& ray) {
  const exact::DomainVerdict verdict = exact::exact_domain(ray, mesh);
  ++exact_counts.by_verdict[int(verdict)];
  ExactAnswers answers;
  if (verdict != exact::DomainVerdict::inside) return answers;
  answers.inside = true;
  answers.read = exact::ray_as_read(ray);
  answers.hits = reference.hits_past_t_min(answers.read);
  return answers;
}

/// Empty when a closest hit and occlusion answer are what the exact reference allows, else the fault.
std::string exact_fault(const ExactAnswers& exact, const Hit& hit, bool occluded) {
  std::string fault = exact::ExactReference::closest_hit_mismatch(exact.read, exact.hits, hit);
  if (fault.empty()) fault = exact::ExactReference::occlusion_mismatch(exact.read, exact.hits, occluded);
  return fault;
}

/// Empty when a structure's answers for a ray agree with brute force's: the same found and occluded, and the same
/// t (a different primitive only where the kernel hits it at exactly brute force's t, a tie). Outside the exact
/// domain, where the library promises no exact t, a different primitive may lie within kFarTTolerance of it
/// (relative; about 8 ulps: a grid walking cells at 1e38 named a triangle one ulp of t behind the closest).
constexpr float kFarTTolerance = 1e-6f;
const char* brute_force_fault(const Scene& scene, const Ray& ray, const Hit& got, bool occluded, const Hit& want,
                              bool inside_exact_domain) {
  if (got.found() != want.found()) return "closest hit found differs";
  if (occluded != want.found()) return "any hit differs";
  if (!want.found()) return nullptr;
  if (got.prim_id == want.prim_id) {
    return std::fabs(got.t - want.t) > kFarTTolerance * std::fabs(want.t) ? "t differs" : nullptr;
  }
  const PreparedRay prepared(ray);
  Hit tie = Hit::begin(prepared);
  if (!scene.intersect(got.prim_id, prepared, tie) || tie.t != got.t) return "another primitive, not hit at its t";
  const float slack = inside_exact_domain ? 0.0f : kFarTTolerance * std::fabs(want.t);
  return std::fabs(tie.t - want.t) > slack ? "another primitive at another t" : nullptr;
}

const std::vector<std::string>& variants() {
  static const std::vector<std::string> names = accelerator_variant_names();
  return names;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 4 || size > 2048) return 0;
  Bytes in(data, size);
  TriangleMesh mesh;
  const int vertex_count = 3 + in.byte() % 14;
  for (int i = 0; i < vertex_count; ++i) mesh.vertices.push_back({in.value(), in.value(), in.value()});
  const int triangle_count = 1 + in.byte() % 12;
  for (int i = 0; i < triangle_count; ++i) {
    mesh.triangles.push_back({std::uint32_t(in.byte() % vertex_count), std::uint32_t(in.byte() % vertex_count),
                              std::uint32_t(in.byte() % vertex_count)});
  }
  std::vector<Ray> rays;
  while (!in.done() && rays.size() < 8) {
    Ray ray;
    ray.origin = {in.value(), in.value(), in.value()};
    const std::uint8_t aim = in.byte();
    if (aim < 128) {  // toward a vertex or an edge midpoint, as a user aiming at the mesh would
      const auto& tri = mesh.triangles[aim % mesh.triangles.size()];
      const Vec3 a = mesh.vertices[tri[aim % 3]], b = mesh.vertices[tri[(aim + 1) % 3]];
      const Vec3 target = (aim & 64) ? (a + b) * 0.5f : a;
      ray.direction = target - ray.origin;
    } else {
      ray.direction = {in.value(), in.value(), in.value()};
    }
    const std::uint8_t bounds = in.byte();
    if (bounds & 1) ray.t_min = in.value();
    if (bounds & 2) ray.t_max = in.value();
    rays.push_back(ray);
  }
  current_mesh = &mesh;
  const Scene scene = Scene::from_mesh(mesh, "fuzz");
  auto oracle = make_accelerator("brute_force");
  oracle->build(scene);
  std::vector<Hit> expected;
  for (const Ray& r : rays) expected.push_back(oracle->intersect(r));
  const exact::ExactReference reference(mesh);
  std::vector<ExactAnswers> exact(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    exact[i] = exact_answers(reference, mesh, rays[i]);
    if (!exact[i].inside) continue;
    const std::string fault = exact_fault(exact[i], expected[i], oracle->occluded(rays[i]));
    if (!fault.empty()) disagree(("against the exact reference: " + fault).c_str(), "brute_force", &rays[i], &expected[i], nullptr);
  }
  for (const std::string& spec : variants()) {
    std::unique_ptr<Accelerator> accel;
    try {
      accel = make_accelerator(spec);
      accel->build(scene);
    } catch (const Error&) {
      continue;  // a structure may refuse a scene with a clear error (none does today)
    }
    if (const auto problems = accel->validate(); !problems.empty()) {
      disagree(problems.front().c_str(), spec, nullptr, nullptr, nullptr);
    }
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const Hit got = accel->intersect(rays[i]);
      const bool occluded = accel->occluded(rays[i]);
      const char* fault = brute_force_fault(scene, rays[i], got, occluded, expected[i], exact[i].inside);
      if (!fault) continue;
      // Inside the exact domain the rule is the library's own: of hits whose exact t lie within their error bounds
      // of each other (or of t_min, t_max) either may be returned. A triangle almost along the ray has a bound
      // of a fraction of its depth range, so brute force and a structure that culls by boxes may rightly differ.
      if (exact[i].inside && exact_fault(exact[i], got, occluded).empty()) continue;
      disagree(fault, spec, &rays[i], &got, &expected[i]);
    }
  }
  return 0;
}
