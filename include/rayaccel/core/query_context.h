// QueryContext: what a renderer says about each ray besides the ray (Embree's ray mask, geometry masks and
// intersection filter): a primitive and a geometry to skip, a ray mask, per-primitive switches and a hit filter.
// ContextStats carries it to the leaves, which call test_candidate() around each primitive test.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>

#include "rayaccel/core/hit.h"
#include "rayaccel/core/stats.h"

namespace rayaccel {

/// A hit a leaf found, offered to a HitFilter before it is kept: the primitive (scene-wide id), its geometry (0 in a
/// scene without a geometry table), the hit's t, u, v, and the ray's index in the batch (0 for a single ray).
struct HitCandidate {
  std::uint32_t prim_id;
  std::uint32_t geom_id;
  float t, u, v;
  std::size_t ray_index;
};

/// Returns true to accept the candidate, false to reject it: traversal then goes on as if the primitive were not
/// there for this ray. Called only for candidates closer than the closest hit accepted so far (any order); it may run
/// on several threads at once for the rays of a batch.
using HitFilter = bool (*)(void* user_data, const HitCandidate& candidate);

/// The optional per-ray controls of a query. Every span may be empty (the control is off); a per-ray span has one entry
/// per ray of the batch (the single-ray forms read entry ray_index); a candidate primitive p of geometry g is tested
/// only when p != skip_primitive[i], g != skip_geometry[i], (ray_mask[i] & geometry_mask[g]) != 0 and
/// primitive_enabled[p] != 0 — all before the exact test (SIMD leaves ask a lone skip of the lanes their float test
/// leaves, before any scalar work) — and then kept only when filter accepts it.
struct QueryContext {
  std::span<const std::uint32_t> skip_primitive;  ///< per ray; kInvalidPrimId skips nothing
  std::span<const std::uint32_t> skip_geometry;   ///< per ray; kInvalidPrimId skips nothing
  std::span<const std::uint32_t> ray_mask;        ///< per ray; empty: every ray's mask is all ones
  /// Geometry k owns primitives [geometry_starts[k], geometry_starts[k + 1]) (GeometryTable::starts()); empty: one
  /// geometry, id 0, holding every primitive.
  std::span<const std::uint32_t> geometry_starts;
  std::span<const std::uint32_t> geometry_mask;      ///< per geometry; empty: all ones. A mask of 0 disables it.
  std::span<const std::uint8_t> primitive_enabled;   ///< per primitive; 0 hides it (opacity, cut-outs)
  HitFilter filter = nullptr;
  void* filter_data = nullptr;

  /// Sets `filter` to call `f(const HitCandidate&) -> bool`, which must outlive the queries (C++ callables, lambdas).
  template <class F>
  void set_filter(F& f) {
    filter = [](void* data, const HitCandidate& c) -> bool { return (*static_cast<F*>(data))(c); };
    filter_data = &f;
  }
  /// The geometry of primitive `prim_id` (0 without geometry_starts; kInvalidPrimId past the last geometry).
  std::uint32_t geometry_of(std::uint32_t prim_id) const {
    if (geometry_starts.empty()) return 0;
    const auto it = std::upper_bound(geometry_starts.begin(), geometry_starts.end(), prim_id);
    if (it == geometry_starts.end()) return kInvalidPrimId;
    return static_cast<std::uint32_t>(it - geometry_starts.begin()) - 1;
  }
};

/// The statistics type a query with a context traces with: it forwards the counts to `Inner` (TraversalStats or
/// NoStats) and answers test_candidate() for ray `ray_index`. Traversals pass their Stats to every leaf, so the
/// context reaches every leaf with no new parameter, and the plain Stats types compile the leaves as before.
template <class Inner>
class ContextStats {
 public:
  ContextStats(const QueryContext& context, std::size_t ray_index, Inner& inner)
      : context_(context), inner_(inner), ray_index_(ray_index) {
    if (!context.skip_primitive.empty()) skip_prim_ = context.skip_primitive[ray_index];
    if (!context.skip_geometry.empty()) skip_geom_ = context.skip_geometry[ray_index];
    if (!context.ray_mask.empty()) mask_ = context.ray_mask[ray_index];
    by_geometry_ = skip_geom_ != kInvalidPrimId || !context.geometry_mask.empty() || mask_ == 0;
  }
  void visit_node(std::uint64_t n = 1) { inner_.visit_node(n); }
  void test_primitive(std::uint64_t n = 1) { inner_.test_primitive(n); }

  /// False when the context rules primitive `prim_id` out for this ray (skip, masks, primitive_enabled).
  bool allows(std::uint32_t prim_id) const {
    if (prim_id == skip_prim_) return false;
    if (!context_.primitive_enabled.empty() &&
        (prim_id >= context_.primitive_enabled.size() || !context_.primitive_enabled[prim_id])) {
      return false;
    }
    if (!by_geometry_) return true;
    const std::uint32_t geom = context_.geometry_of(prim_id);
    if (skip_geom_ != kInvalidPrimId && geom == skip_geom_) return false;
    const std::uint32_t geom_mask =
        context_.geometry_mask.empty() || geom >= context_.geometry_mask.size() ? ~0u : context_.geometry_mask[geom];
    return (mask_ & geom_mask) != 0;
  }
  /// True when a rule other than the skipped primitive is on (primitive switches, masks, a skipped geometry): such
  /// rules may rule out whole blocks of a leaf, so SIMD leaves ask allows() of every lane before the test. With only
  /// a skipped primitive (a secondary ray's origin surface) they test first and ask it of the lanes that hit.
  bool rules_out_blocks() const { return by_geometry_ || !context_.primitive_enabled.empty(); }
  bool has_filter() const { return context_.filter != nullptr; }
  /// The filter's answer for a hit that passed allows() and the exact test.
  bool accepts(const Hit& candidate) const {
    const HitCandidate c{candidate.prim_id, context_.geometry_of(candidate.prim_id), candidate.t, candidate.u,
                         candidate.v, ray_index_};
    return context_.filter(context_.filter_data, c);
  }

 private:
  const QueryContext& context_;
  Inner& inner_;
  std::size_t ray_index_;
  std::uint32_t skip_prim_ = kInvalidPrimId;
  std::uint32_t skip_geom_ = kInvalidPrimId;
  std::uint32_t mask_ = ~0u;
  bool by_geometry_ = false;
};

template <class Stats>
inline constexpr bool kHasContext = false;
template <class Inner>
inline constexpr bool kHasContext<ContextStats<Inner>> = true;

/// The one leaf hook: runs `test(hit)` (the exact test of primitive `prim_id`, which updates `hit` with a closer hit
/// and returns true) unless the context rules the primitive out, and keeps its hit only when the filter accepts it.
/// With plain Stats it is `test(hit)` and nothing else. Returns true when `hit` changed.
template <class Stats, class Test>
inline bool test_candidate(const Stats& stats, std::uint32_t prim_id, Hit& hit, Test&& test) {
  if constexpr (!kHasContext<std::remove_const_t<Stats>>) {
    return test(hit);
  } else {
    if (!stats.allows(prim_id)) return false;
    if (!stats.has_filter()) return test(hit);
    Hit candidate = hit;
    if (!test(candidate) || !stats.accepts(candidate)) return false;
    hit = candidate;
    return true;
  }
}

}  // namespace rayaccel
