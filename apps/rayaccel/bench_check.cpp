// The check `rayaccel bench` runs before timing: every structure against Embree on every ray (disagreements and a
// sample settled by brute force, the oracle), else against brute force on a sample; the rules: docs/design.md.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "bench.h"
#include "rayaccel/generalized/generalized_rays.h"

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

/// Positions 0..count-1 spread evenly over n (all of them when count == n).
std::vector<std::size_t> spread(std::size_t n, std::size_t count) {
  std::vector<std::size_t> positions(count);
  for (std::size_t i = 0; i < count; ++i) positions[i] = count == n ? i : i * n / count;
  return positions;
}

/// A foreign kernel's closest hit against brute force's: both miss, or both hit at t within `relative` of each
/// other, on any primitive (another kernel's rounding may pick the other side of a near tie).
bool agrees_as_foreign(const Hit& got, const Hit& want, float relative) {
  if (got.found() != want.found()) return false;
  return !got.found() || std::fabs(got.t - want.t) <= relative * std::fabs(want.t);
}

/// The beam kind's whole image by the structure's beams (default options), or, for a structure without them,
/// intersect_packets() over the rays in row order.
void trace_by_beams(const Accelerator& accel, const Workload& w, std::span<Hit> hits) {
  if (!generalized::supports_generalized_rays(accel)) {
    accel.intersect_packets(w.rays, hits);
    return;
  }
  const auto beams = generalized::make_generalized_rays(accel, *w.scene);
  const CameraFrame& frame = w.frame;
  const generalized::PixelRays pixels{frame.width, frame.height,
                                      [&frame](float x, float y) { return frame.ray_at(x, y); }, w.rays};
  beams->trace_beams(pixels, generalized::BeamOptions{}, hits);
}

}  // namespace

void trace_rays(const Accelerator& accel, const Workload& w, std::span<const Ray> rays,
                std::span<const std::uint32_t> skip, std::span<Hit> hits, std::span<std::uint8_t> occluded,
                bool packets) {
  if (w.kind == RayKind::beam && packets) {  // whole images only (the rays are the workload's)
    trace_by_beams(accel, w, hits);
    return;
  }
  QueryContext context;
  context.skip_primitive = skip;
  if (w.any_hit() && packets) {
    accel.occluded_packets(rays, occluded);
  } else if (packets) {
    accel.intersect_packets(rays, hits);
  } else if (w.any_hit() && w.skips()) {
    accel.occluded(context, rays, occluded);
  } else if (w.any_hit()) {
    accel.occluded(rays, occluded);
  } else if (w.skips()) {
    accel.intersect(context, rays, hits);
  } else {
    accel.intersect(rays, hits);
  }
}

std::vector<Ray> trace_workload(const Accelerator& accel, const Workload& w, const std::vector<std::size_t>& ids,
                                std::vector<Hit>& hits, std::vector<std::uint8_t>& occluded, bool ray_by_ray) {
  std::vector<Ray> rays(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) rays[i] = w.rays[ids[i]];
  hits.assign(w.any_hit() ? 0 : rays.size(), Hit{});
  occluded.assign(w.any_hit() ? rays.size() : 0, 0);
  if (w.packets() && !ray_by_ray) {
    std::vector<Hit> all_hits(hits.empty() ? 0 : w.rays.size());
    std::vector<std::uint8_t> all_occluded(occluded.empty() ? 0 : w.rays.size());
    trace_rays(accel, w, w.rays, w.skip, all_hits, all_occluded, true);
    for (std::size_t i = 0; i < ids.size(); ++i) {
      if (w.any_hit()) {
        occluded[i] = all_occluded[ids[i]];
      } else {
        hits[i] = all_hits[ids[i]];
      }
    }
    return rays;
  }
  std::vector<std::uint32_t> skip(w.skips() ? ids.size() : 0);
  for (std::size_t i = 0; i < skip.size(); ++i) skip[i] = w.skip[ids[i]];
  trace_rays(accel, w, rays, skip, hits, occluded, false);
  return rays;
}

ReferenceCheck::ReferenceCheck(const Scene& scene, const std::vector<Workload>& workloads, const Accelerator* embree,
                               std::size_t sample_size)
    : scene_(scene), workloads_(workloads), from_embree_(embree != nullptr), sample_size_(sample_size) {
  oracle_.build(scene);
  settled_.resize(workloads.size());
  for (const Workload& w : workloads) {
    Answers a;
    const std::size_t n = w.rays.size();
    a.indices = spread(n, from_embree_ ? n : std::min(n, sample_size));
    if (from_embree_) a.sample = spread(n, std::min(n, sample_size));
    const Accelerator& reference = from_embree_ ? *embree : static_cast<const Accelerator&>(oracle_);
    trace_workload(reference, w, a.indices, a.hits, a.occluded, true);
    answers_.push_back(std::move(a));
  }
  // Brute force's answers on the sample, once: every structure is checked against them besides Embree's.
  for (std::size_t k = 0; k < workloads.size(); ++k) settle(k, answers_[k].sample);
}

std::string ReferenceCheck::description() const {
  return from_embree_ ? fmt::format("embree on every ray, disagreements and a sample of up to {} rays per ray kind "
                                    "settled by brute force",
                                    sample_size_)
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
  std::vector<std::size_t> ids(pending.size());
  for (std::size_t j = 0; j < pending.size(); ++j) ids[j] = answers_[workload].indices[pending[j]];
  std::vector<Hit> hits;
  std::vector<std::uint8_t> occluded;
  trace_workload(oracle_, w, ids, hits, occluded, true);
  for (std::size_t j = 0; j < pending.size(); ++j) {
    if (w.any_hit()) {
      settled[pending[j]].occluded = occluded[j] != 0;
    } else {
      settled[pending[j]].hit = hits[j];
    }
  }
}

void ReferenceCheck::check(const Accelerator& accel, std::vector<KindResult>& kinds) const {
  for (std::size_t k = 0; k < workloads_.size(); ++k) {
    const Workload& w = workloads_[k];
    const Answers& a = answers_[k];
    KindResult& result = kinds[k];
    std::vector<Hit> hits;
    std::vector<std::uint8_t> occluded;
    const std::vector<Ray> rays = trace_workload(accel, w, a.indices, hits, occluded);
    result.checked = rays.size();
    // First pass: answers the reference accepts, and rays to settle by brute force (Embree's disagreements).
    std::vector<std::size_t> disagreements;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const bool agrees = w.any_hit()     ? occluded[i] == a.occluded[i]
                          : from_embree_ ? same_primitive(hits[i], a.hits[i])
                                          : agrees_with_oracle(hits[i], a.hits[i]);
      if (!agrees) disagreements.push_back(i);
    }
    std::vector<bool> disagrees(rays.size(), false);
    if (!from_embree_) {
      for (std::size_t i : disagreements) disagrees[i] = true;
    } else {
      // Brute force decides every disagreement with Embree, and every ray of the sample, where the structure could
      // agree with Embree and both be wrong.
      settle(k, disagreements);
      std::vector<bool> decide(rays.size(), false), differs_from_embree(rays.size(), false);
      for (std::size_t i : disagreements) decide[i] = differs_from_embree[i] = true;
      for (std::size_t i : a.sample) decide[i] = true;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!decide[i]) continue;
        const Settled& truth = settled_[k].at(i);
        const bool ok = w.any_hit() ? (occluded[i] != 0) == truth.occluded : agrees_with_oracle(hits[i], truth.hit);
        if (!ok) disagrees[i] = true;
        if (ok && differs_from_embree[i]) ++result.reference_differences;
      }
    }
    // Second pass: every answer brute force rejected, and every closest hit whose t, u, v are not the kernel's for
    // the primitive it names, is a mismatch.
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

void ReferenceCheck::check_foreign(const Accelerator& foreign, std::vector<KindResult>& kinds) const {
  if (!from_embree_) return;
  for (std::size_t k = 0; k < workloads_.size(); ++k) {
    const Workload& w = workloads_[k];
    const Answers& a = answers_[k];
    KindResult& result = kinds[k];
    std::vector<std::size_t> ids(a.sample.size());
    for (std::size_t j = 0; j < ids.size(); ++j) ids[j] = a.indices[a.sample[j]];
    std::vector<Hit> hits;
    std::vector<std::uint8_t> occluded;
    const std::vector<Ray> rays = trace_workload(foreign, w, ids, hits, occluded);
    result.checked = rays.size();
    std::size_t examples = 0;
    for (std::size_t j = 0; j < rays.size(); ++j) {
      const Settled& truth = settled_[k].at(a.sample[j]);
      const bool ok = w.any_hit() ? (occluded[j] != 0) == truth.occluded
                                  : agrees_as_foreign(hits[j], truth.hit, kForeignRelativeT);
      if (ok) continue;
      ++result.foreign_differences;
      if (examples++ >= kExamples) continue;
      const std::string got = w.any_hit() ? (occluded[j] ? "occluded" : "not occluded") : describe(hits[j]);
      const std::string want = w.any_hit() ? (truth.occluded ? "occluded" : "not occluded") : describe(truth.hit);
      std::cerr << fmt::format("note: {} differs from brute force on {} {} ray {}: got {}, brute force {}; ray {}\n",
                               foreign.spec(), scene_.name(), to_string(w.kind), ids[j], got, want,
                               describe(rays[j]));
    }
  }
}

}  // namespace rayaccel::cli
