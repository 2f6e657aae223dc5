// libFuzzer target: a differential test of every registered structure variant against brute force on a small
// fuzzed scene. The input's bytes become up to 12 triangles and 8 rays; each coordinate byte picks a value from a
// table of hostile floats (0, -0, subnormals, 1e-30, 1, huge, FLT_MAX, Inf, NaN) or a raw float, so NaN, Inf,
// subnormal, huge and duplicate vertices are common. Answers must match the oracle's as in the conformance suite:
// same found/occluded, and the same t (a different primitive only at exactly the same t).
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

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

/// Stops the run on a disagreement, printing what disagreed first so that a CI log names it.
[[noreturn]] void disagree(const char* what, const std::string& spec, const Ray* ray, const Hit* got, const Hit* want) {
  std::fprintf(stderr, "fuzz_differential: %s: %s\n", spec.c_str(), what);
  if (ray) {
    std::fprintf(stderr, "  ray origin (%a, %a, %a) direction (%a, %a, %a) t (%a, %a]\n", ray->origin.x, ray->origin.y,
                 ray->origin.z, ray->direction.x, ray->direction.y, ray->direction.z, ray->t_min, ray->t_max);
  }
  if (got) std::fprintf(stderr, "  got prim %u t %a\n", unsigned(got->prim_id), got->t);
  if (want) std::fprintf(stderr, "  brute force prim %u t %a\n", unsigned(want->prim_id), want->t);
  __builtin_trap();
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
  const Scene scene = Scene::from_mesh(mesh, "fuzz");
  auto oracle = make_accelerator("brute_force");
  oracle->build(scene);
  std::vector<Hit> expected;
  for (const Ray& r : rays) expected.push_back(oracle->intersect(r));
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
      const Hit& want = expected[i];
      if (got.found() != want.found()) disagree("closest hit found differs", spec, &rays[i], &got, &want);
      if (accel->occluded(rays[i]) != want.found()) disagree("any hit differs", spec, &rays[i], &got, &want);
      if (!want.found()) continue;
      if (got.prim_id == want.prim_id) {
        if (std::fabs(got.t - want.t) > 1e-6f * std::fabs(want.t)) disagree("t differs", spec, &rays[i], &got, &want);
        continue;
      }
      // A different primitive: the kernel must hit it at exactly the oracle's t (a tie).
      const PreparedRay prepared(rays[i]);
      Hit tie = Hit::begin(prepared);
      if (!scene.intersect(got.prim_id, prepared, tie) || tie.t != want.t) {
        disagree("another primitive at another t", spec, &rays[i], &got, &want);
      }
    }
  }
  return 0;
}
