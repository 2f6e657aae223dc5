// The check `rayaccel bench` runs before timing anything: every structure's answers against Embree for every ray
// (every disagreement then settled by brute force, the oracle) or, without Embree, against brute force on a sample.
// Closest hits must name the oracle's primitive or an exact tie in t, and carry exactly the t, u, v that the shared
// triangle kernel gives for the primitive they name.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "bench.h"

namespace rayaccel::cli {

namespace {

constexpr std::size_t kExamples = 5;

/// Both miss, or both name the same primitive (Embree's answer: its t, u, v come from another kernel, and the
/// structure's own are checked against ours by kernel_fault()).
bool same_primitive(const Hit& got, const Hit& want) {
  return got.found() == want.found() && (!got.found() || got.prim_id == want.prim_id);
}

/// The oracle's answer, or an exact tie: another primitive hit at exactly the oracle's t.
bool agrees_with_oracle(const Hit& got, const Hit& want) {
  if (got.found() != want.found()) return false;
  if (!got.found()) return true;
  return got.prim_id == want.prim_id ? got.t == want.t && got.u == want.u && got.v == want.v : got.t == want.t;
}

}  // namespace

std::string kernel_fault(const Scene& scene, const Ray& ray, const Hit& hit) {
  if (!hit.found()) {
    return std::isinf(hit.t) && hit.t > 0.0f && hit.u == 0.0f && hit.v == 0.0f ? "" : "a miss must be t=+inf, u=v=0";
  }
  if (hit.prim_id >= scene.primitive_count()) return fmt::format("prim {} does not exist", hit.prim_id);
  const PreparedRay prepared(ray);
  Hit check = Hit::begin(prepared);
  if (!scene.intersect(hit.prim_id, prepared, check)) return fmt::format("prim {} is not hit by this ray", hit.prim_id);
  if (check.t != hit.t || check.u != hit.u || check.v != hit.v) {
    return fmt::format("the kernel hits prim {} at t={:.9g} u={:.9g} v={:.9g}", hit.prim_id, check.t, check.u,
                       check.v);
  }
  return "";
}

namespace {

std::string describe(const Hit& h) {
  return h.found() ? fmt::format("t={:.9g} prim={} u={:.9g} v={:.9g}", h.t, h.prim_id, h.u, h.v) : std::string("miss");
}

std::string describe(const Ray& r) {
  return fmt::format("o=({:.9g},{:.9g},{:.9g}) d=({:.9g},{:.9g},{:.9g}) t=[{:.9g},{:.9g}]", r.origin.x, r.origin.y,
                     r.origin.z, r.direction.x, r.direction.y, r.direction.z, r.t_min, r.t_max);
}
}  // namespace

ReferenceCheck::ReferenceCheck(const Scene& scene, const std::vector<Workload>& workloads, const Accelerator* embree,
                               std::size_t sample_size)
    : scene_(scene), workloads_(workloads), from_embree_(embree != nullptr), sample_size_(sample_size) {
  oracle_.build(scene);
  settled_.resize(workloads.size());
  for (const Workload& w : workloads) {
    Answers a;
    const std::size_t n = w.rays.size();
    const std::size_t count = from_embree_ ? n : std::min(n, sample_size);
    a.indices.resize(count);
    for (std::size_t i = 0; i < count; ++i) a.indices[i] = count == n ? i : i * n / count;
    std::vector<Ray> rays(count);
    for (std::size_t i = 0; i < count; ++i) rays[i] = w.rays[a.indices[i]];
    const Accelerator& reference = from_embree_ ? *embree : static_cast<const Accelerator&>(oracle_);
    if (w.any_hit()) {
      a.occluded.resize(count);
      reference.occluded(rays, a.occluded);
    } else {
      a.hits.resize(count);
      reference.intersect(rays, a.hits);
    }
    answers_.push_back(std::move(a));
  }
}

std::string ReferenceCheck::description() const {
  return from_embree_ ? std::string("embree on every ray, disagreements settled by brute force")
                      : fmt::format("brute force on a sample of up to {} rays per ray kind", sample_size_);
}

void ReferenceCheck::settle(std::size_t workload, const std::vector<std::size_t>& indices) const {
  const Workload& w = workloads_[workload];
  auto& settled = settled_[workload];
  std::vector<std::size_t> pending;
  for (std::size_t i : indices) {
    if (!settled.count(i)) pending.push_back(i);
  }
  if (pending.empty()) return;
  // One parallel brute-force batch for every new disagreement; the answers are kept for the next structures.
  std::vector<Ray> rays(pending.size());
  for (std::size_t j = 0; j < pending.size(); ++j) rays[j] = w.rays[answers_[workload].indices[pending[j]]];
  if (w.any_hit()) {
    std::vector<std::uint8_t> occluded(rays.size());
    oracle_.occluded(rays, occluded);
    for (std::size_t j = 0; j < pending.size(); ++j) settled[pending[j]].occluded = occluded[j] != 0;
  } else {
    std::vector<Hit> hits(rays.size());
    oracle_.intersect(rays, hits);
    for (std::size_t j = 0; j < pending.size(); ++j) settled[pending[j]].hit = hits[j];
  }
}

void ReferenceCheck::check(const Accelerator& accel, std::vector<KindResult>& kinds) const {
  for (std::size_t k = 0; k < workloads_.size(); ++k) {
    const Workload& w = workloads_[k];
    const Answers& a = answers_[k];
    KindResult& result = kinds[k];
    std::vector<Ray> rays(a.indices.size());
    for (std::size_t i = 0; i < rays.size(); ++i) rays[i] = w.rays[a.indices[i]];
    std::vector<Hit> hits(w.any_hit() ? 0 : rays.size());
    std::vector<std::uint8_t> occluded(w.any_hit() ? rays.size() : 0);
    if (w.any_hit()) {
      accel.occluded(rays, occluded);
    } else if (w.packets()) {
      // The packets of the whole workload, as timed; a sample's rays put together would not be its packets.
      std::vector<Hit> all(w.rays.size());
      accel.intersect_packets(w.rays, all);
      for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = all[a.indices[i]];
    } else {
      accel.intersect(rays, hits);
    }
    result.checked = rays.size();
    // First pass: answers the reference accepts, and rays to settle by brute force (Embree's disagreements).
    std::vector<std::size_t> disagreements;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const bool agrees = w.any_hit()     ? occluded[i] == a.occluded[i]
                          : from_embree_ ? same_primitive(hits[i], a.hits[i])
                                          : agrees_with_oracle(hits[i], a.hits[i]);
      if (!agrees) disagreements.push_back(i);
    }
    if (from_embree_) settle(k, disagreements);
    std::vector<bool> settled_ok(rays.size(), false);
    for (std::size_t i : disagreements) {
      if (!from_embree_) continue;
      const Settled& truth = settled_[k].at(i);
      settled_ok[i] = w.any_hit() ? (occluded[i] != 0) == truth.occluded : agrees_with_oracle(hits[i], truth.hit);
      if (settled_ok[i]) ++result.reference_differences;
    }
    // Second pass: every disagreement the oracle did not settle, and every closest hit whose t, u, v are not the
    // kernel's for the primitive it names, is a mismatch.
    std::vector<bool> disagrees(rays.size(), false);
    for (std::size_t i : disagreements) disagrees[i] = !settled_ok[i];
    std::size_t examples = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const std::string fault = w.any_hit() ? std::string() : kernel_fault(scene_, rays[i], hits[i]);
      if (!disagrees[i] && fault.empty()) continue;
      ++result.mismatches;
      if (examples++ >= kExamples) continue;
      const std::string got = w.any_hit() ? (occluded[i] ? "occluded" : "not occluded") : describe(hits[i]);
      const std::string want = w.any_hit() ? (a.occluded[i] ? "occluded" : "not occluded") : describe(a.hits[i]);
      std::string oracle_text;
      if (from_embree_ && settled_[k].count(i)) {
        const Settled& truth = settled_[k].at(i);
        oracle_text = w.any_hit() ? (truth.occluded ? "occluded" : "not occluded") : describe(truth.hit);
      }
      std::cerr << fmt::format("MISMATCH {} on {} {} ray {}: got {}, reference {}{}{}; ray {}\n", accel.spec(),
                               scene_.name(), to_string(w.kind), a.indices[i], got, want,
                               oracle_text.empty() ? "" : ", brute force " + oracle_text,
                               fault.empty() ? "" : ", " + fault, describe(rays[i]));
    }
    if (result.mismatches > 0) {
      std::cerr << fmt::format("MISMATCH {} on {} {}: {} of {} rays disagree with the reference\n", accel.spec(),
                               scene_.name(), to_string(w.kind), result.mismatches, result.checked);
    }
  }
}

}  // namespace rayaccel::cli
