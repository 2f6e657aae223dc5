// EmbreeAccelerator: one Embree device and scene over a padded vertex copy and the valid triangles (ids mapped back),
// rays mapped to RTCRay with tnear just above t_min so Embree's [tnear, tfar] matches (t_min, t_max].
#include "rayaccel/compare/embree_accelerator.h"

#include "rayaccel/accel/registry_extension.h"

#ifdef RAYACCEL_HAVE_EMBREE

#include <embree3/rtcore.h>
#include <xmmintrin.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/core/float_rounding.h"
#include "rayaccel/core/query_context.h"

namespace rayaccel {

struct EmbreeAccelerator::State {
  EmbreeOptions options;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  const Scene* source = nullptr;
  std::vector<float> vertices;  ///< x y z per vertex plus 4 bytes of padding Embree may read past the last one
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< the valid triangles, in id order
  std::vector<std::uint32_t> prim_ids;                  ///< scene id of each of them (Embree's primID -> ours)
  std::atomic<std::int64_t> allocated{0};  ///< bytes Embree holds now (memory monitor)
  std::int64_t scene_bytes = 0;            ///< bytes the committed scene kept
  std::string last_error;

  void release_scene() {
    if (scene) rtcReleaseScene(scene);
    scene = nullptr;
  }
};

namespace {

RTCBuildQuality to_embree(EmbreeBuildQuality quality) {
  switch (quality) {
    case EmbreeBuildQuality::low: return RTC_BUILD_QUALITY_LOW;
    case EmbreeBuildQuality::medium: return RTC_BUILD_QUALITY_MEDIUM;
    case EmbreeBuildQuality::high: return RTC_BUILD_QUALITY_HIGH;
  }
  return RTC_BUILD_QUALITY_MEDIUM;
}

/// Embree accepts tnear <= t <= tfar; the next float above t_min turns that into t_min < t (the same inline helper
/// rayaccel's own Hit::begin() uses, so neither side pays a libm call per ray).
float embree_tnear(const Ray& ray) { return next_float_up(ray.t_min); }

/// Fills an RTCRay from a ray that is not void with t_min < t_max.
void to_embree(const Ray& ray, RTCRay& out) {
  out.org_x = ray.origin.x;
  out.org_y = ray.origin.y;
  out.org_z = ray.origin.z;
  out.tnear = embree_tnear(ray);
  out.dir_x = ray.direction.x;
  out.dir_y = ray.direction.y;
  out.dir_z = ray.direction.z;
  out.time = 0.0f;
  out.tfar = ray.t_max;
  out.mask = 0xFFFFFFFFu;
  out.id = 0;
  out.flags = 0;
}

/// Fills lane `lane` of an RTCRay8 from a ray that is not void with t_min < t_max, as to_embree() does.
void to_embree(const Ray& ray, RTCRay8& r, int lane) {
  r.org_x[lane] = ray.origin.x;
  r.org_y[lane] = ray.origin.y;
  r.org_z[lane] = ray.origin.z;
  r.tnear[lane] = embree_tnear(ray);
  r.dir_x[lane] = ray.direction.x;
  r.dir_y[lane] = ray.direction.y;
  r.dir_z[lane] = ray.direction.z;
  r.time[lane] = 0.0f;
  r.tfar[lane] = ray.t_max;
  r.mask[lane] = 0xFFFFFFFFu;
  r.id[lane] = 0;
  r.flags[lane] = 0;
}

/// Fills lane `lane` of an RTCRayHit8 the same way, with no hit recorded yet.
void to_embree(const Ray& ray, RTCRayHit8& out, int lane) {
  to_embree(ray, out.ray, lane);
  out.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
  out.hit.primID[lane] = RTC_INVALID_GEOMETRY_ID;
}

/// Rays that can hold no hit under t_min < t <= t_max: void rays (PreparedRay's rule, without PreparedRay's divisions,
/// which would be charged to Embree's time) and empty intervals.
bool cannot_hit(const Ray& ray) { return !is_valid_ray(ray) || !(ray.t_min < ray.t_max); }

/// Fills the lanes of `packet` (an RTCRay8 or RTCRayHit8) from `rays` (at most eight): valid[lane] is -1 for a lane
/// that is filled, 0 for one past the rays or whose ray cannot hit (inactive). Returns whether any lane is active.
template <class Packet>
bool fill_packet(std::span<const Ray> rays, int* valid, Packet& packet) {
  bool any = false;
  for (std::size_t lane = 0; lane < detail::kPacketSize; ++lane) {
    const bool active = lane < rays.size() && !cannot_hit(rays[lane]);
    valid[lane] = active ? -1 : 0;
    if (active) {
      to_embree(rays[lane], packet, static_cast<int>(lane));
      any = true;
    }
  }
  return any;
}

}  // namespace

EmbreeAccelerator::EmbreeAccelerator(EmbreeOptions options) : state_(std::make_unique<State>()) {
  embree_option_table().check(options);
  state_->options = options;
  const std::string config = options.threads > 0 ? "threads=" + std::to_string(options.threads) : std::string();
  state_->device = rtcNewDevice(config.c_str());
  if (!state_->device) {
    throw Error("embree: cannot create a device with config '" + config + "' (error " +
                std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  }
  // Captureless lambdas: they convert to Embree's C callbacks and may name the private State.
  rtcSetDeviceErrorFunction(
      state_->device,
      [](void* user, RTCError code, const char* message) {
        static_cast<State*>(user)->last_error =
            "embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
      },
      state_.get());
  rtcSetDeviceMemoryMonitorFunction(
      state_->device,
      [](void* user, ssize_t bytes, bool /*post*/) {
        static_cast<State*>(user)->allocated.fetch_add(bytes, std::memory_order_relaxed);
        return true;
      },
      state_.get());
}

EmbreeAccelerator::~EmbreeAccelerator() {
  state_->release_scene();
  rtcReleaseDevice(state_->device);
}

void EmbreeAccelerator::build(const Scene& scene) {
  if (scene.kind() != PrimitiveKind::triangles) throw Error("embree comparison supports triangle scenes only");
  if (scene.borrows_buffers()) throw Error("embree comparison needs a scene that owns its mesh (Scene::from_mesh)");
  State& s = *state_;
  s.release_scene();
  s.source = &scene;
  s.last_error.clear();
  const TriangleMesh& mesh = scene.mesh();
  s.triangles.clear();
  s.prim_ids.clear();
  for (std::uint32_t id = 0; id < scene.primitive_count(); ++id) {
    if (!scene.is_valid(id)) continue;
    s.triangles.push_back(mesh.triangles[id]);
    s.prim_ids.push_back(id);
  }
  s.vertices.assign(mesh.vertices.size() * 3 + 1, 0.0f);
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    s.vertices[3 * i] = mesh.vertices[i].x;
    s.vertices[3 * i + 1] = mesh.vertices[i].y;
    s.vertices[3 * i + 2] = mesh.vertices[i].z;
  }
  const std::int64_t before = s.allocated.load();
  s.scene = rtcNewScene(s.device);
  rtcSetSceneBuildQuality(s.scene, to_embree(s.options.quality));
  int flags = RTC_SCENE_FLAG_NONE;
  if (s.options.robust) flags |= RTC_SCENE_FLAG_ROBUST;
  if (s.options.context_filter) flags |= RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION;
  rtcSetSceneFlags(s.scene, static_cast<RTCSceneFlags>(flags));
  if (!s.triangles.empty()) {
    RTCGeometry geometry = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, s.vertices.data(), 0,
                               3 * sizeof(float), mesh.vertices.size());
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, s.triangles.data(), 0,
                               sizeof(s.triangles[0]), s.triangles.size());
    rtcSetGeometryBuildQuality(geometry, to_embree(s.options.quality));
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(s.scene, geometry);
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(s.scene);
  s.scene_bytes = s.allocated.load() - before;
  if (!s.last_error.empty()) throw Error("embree build failed: " + s.last_error);
}

namespace {

/// Flush-to-zero and denormals-are-zero for the lifetime of the object, the MXCSR setting Embree's documentation
/// asks applications to make for speed (what it changes: BENCHMARKS.md, "Floating-point environment"), so batches
/// time Embree as its users run it. The caller's setting is restored on exit.
class EmbreeFloatMode {
 public:
  EmbreeFloatMode() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | kFlushToZero | kDenormalsAreZero); }
  ~EmbreeFloatMode() { _mm_setcsr(saved_); }
  EmbreeFloatMode(const EmbreeFloatMode&) = delete;
  EmbreeFloatMode& operator=(const EmbreeFloatMode&) = delete;

 private:
  static constexpr unsigned kFlushToZero = 0x8000;
  static constexpr unsigned kDenormalsAreZero = 0x0040;
  unsigned saved_;
};


/// The loop both packet queries share: ranges of whole packets over the threads, each with Embree's float mode and a
/// coherent context; each packet filled once (fill_packet), traced by `trace(valid, context, query)` when a lane is
/// live, then every lane's answer stored by `store(ray index, lane live, query, lane)`. Nothing built: every lane is
/// stored as not live.
template <class Query, class Trace, class Store>
void trace_packets(std::span<const Ray> rays, RTCScene scene, Trace&& trace, Store&& store) {
  constexpr std::size_t kLanes = detail::kPacketSize;
  static_assert(kLanes == 8, "one rtcIntersect8 / rtcOccluded8 call per packet");
  detail::parallel_for_packets(rays.size(), [&](std::size_t begin, std::size_t end) {
    const EmbreeFloatMode mode;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(32) int valid[kLanes] = {};
    Query query{};  // 32-byte aligned (RTC_ALIGN(32) members); inactive lanes keep defined values
    for (std::size_t first = begin; first < end; first += kLanes) {
      const std::size_t count = std::min(kLanes, end - first);
      if (scene && fill_packet(rays.subspan(first, count), valid, query)) trace(valid, context, query);
      for (std::size_t lane = 0; lane < count; ++lane) store(first + lane, scene && valid[lane] != 0, query, lane);
    }
  });
}

}  // namespace

namespace {

/// What a single-ray query reads of the built scene.
struct Built {
  RTCScene scene;
  const std::vector<std::uint32_t>& prim_ids;  ///< Embree's primID -> the scene's id
};

/// The closest hit of one ray under an Embree intersect context (a plain one, or a FilteredContext's).
Hit intersect_in(const Built& built, RTCIntersectContext& context, const Ray& ray) {
  Hit hit;
  if (!built.scene || cannot_hit(ray)) return hit;
  RTCRayHit query;
  to_embree(ray, query.ray);
  query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  query.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(built.scene, &context, &query);
  if (query.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
    hit.t = query.ray.tfar;
    hit.prim_id = built.prim_ids[query.hit.primID];
    hit.u = query.hit.u;
    hit.v = query.hit.v;
  }
  return hit;
}

/// Whether one ray is occluded under an Embree intersect context; Embree marks it by tfar = -inf.
bool occluded_in(const Built& built, RTCIntersectContext& context, const Ray& ray) {
  if (!built.scene || cannot_hit(ray)) return false;
  RTCRay query;
  to_embree(ray, query);
  rtcOccluded1(built.scene, &context, &query);
  return query.tfar == -std::numeric_limits<float>::infinity();
}

/// The intersect context of a query with a QueryContext: Embree hands its address back to context_filter(), which
/// finds the ray's rules and the id map beside it.
struct FilteredContext {
  RTCIntersectContext rtc;  // first: its address is the object's
  const ContextStats<NoStats>* rules;
  const std::vector<std::uint32_t>* prim_ids;
};

/// Embree's context filter: clears valid[i] for a candidate the rules rule out or the user's filter rejects, so that
/// Embree drops it and traverses on (Embree passes the candidate's distance as the ray's tfar).
void context_filter(const RTCFilterFunctionNArguments* args) {
  const auto* context = reinterpret_cast<const FilteredContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    Hit candidate;
    candidate.prim_id = (*context->prim_ids)[RTCHitN_primID(args->hit, args->N, i)];
    bool keep = context->rules->allows(candidate.prim_id);
    if (keep && context->rules->has_filter()) {
      candidate.t = RTCRayN_tfar(args->ray, args->N, i);
      candidate.u = RTCHitN_u(args->hit, args->N, i);
      candidate.v = RTCHitN_v(args->hit, args->N, i);
      keep = context->rules->accepts(candidate);
    }
    if (!keep) args->valid[i] = 0;
  }
}

/// Error unless the scene was committed with the context-filter flag (Embree would never call the filter).
void require_context_filter(bool has_filter_flag) {
  if (!has_filter_flag) {
    throw Error("embree: queries with a context (skip, masks, filters) need the scene's context filter: "
                "embree:filter=1");
  }
}

/// Runs query(rtc) with an Embree context whose filter applies `context`'s rules for ray `ray_index`.
template <class Query>
auto with_context(const std::vector<std::uint32_t>& prim_ids, const QueryContext& context, std::size_t ray_index,
                  Query&& query) {
  NoStats none;
  const ContextStats<NoStats> rules(context, ray_index, none);
  FilteredContext filtered{{}, &rules, &prim_ids};
  rtcInitIntersectContext(&filtered.rtc);
  filtered.rtc.filter = context_filter;
  return query(filtered.rtc);
}

/// The batches' loop: ranges of rays over the threads, each in Embree's float mode, answer(i) for ray i.
template <class Answer>
void for_each_ray(std::size_t count, Answer&& answer) {
  detail::parallel_for_rays(count, [&](std::size_t begin, std::size_t end) {
    const EmbreeFloatMode mode;
    for (std::size_t i = begin; i < end; ++i) answer(i);
  });
}

}  // namespace

Hit EmbreeAccelerator::intersect(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  return intersect_in({state_->scene, state_->prim_ids}, context, ray);
}

Hit EmbreeAccelerator::intersect(const Ray& ray, TraversalStats&) const { return intersect(ray); }

bool EmbreeAccelerator::occluded(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  return occluded_in({state_->scene, state_->prim_ids}, context, ray);
}

bool EmbreeAccelerator::occluded(const Ray& ray, TraversalStats&) const { return occluded(ray); }

void EmbreeAccelerator::intersect(std::span<const Ray> rays, std::span<Hit> hits,
                                  std::span<TraversalStats> stats) const {
  detail::check_batch_sizes(rays.size(), hits.size(), stats.size());
  for_each_ray(rays.size(), [&](std::size_t i) { hits[i] = intersect(rays[i]); });
}

void EmbreeAccelerator::intersect_packets(std::span<const Ray> rays, std::span<Hit> hits) const {
  detail::check_batch_sizes(rays.size(), hits.size(), 0);
  trace_packets<RTCRayHit8>(
      rays, state_->scene,
      [&](const int* valid, RTCIntersectContext& context, RTCRayHit8& query) {
        rtcIntersect8(valid, state_->scene, &context, &query);
      },
      // Each record written whole and once, as rayaccel's packet traversal writes its own (a miss is Hit{}).
      [&](std::size_t index, bool valid, const RTCRayHit8& query, std::size_t lane) {
        Hit hit;
        if (valid && query.hit.geomID[lane] != RTC_INVALID_GEOMETRY_ID) {
          hit.t = query.ray.tfar[lane];
          hit.prim_id = state_->prim_ids[query.hit.primID[lane]];
          hit.u = query.hit.u[lane];
          hit.v = query.hit.v[lane];
        }
        hits[index] = hit;
      });
}

void EmbreeAccelerator::occluded_packets(std::span<const Ray> rays, std::span<std::uint8_t> occluded_out) const {
  detail::check_batch_sizes(rays.size(), occluded_out.size(), 0);
  trace_packets<RTCRay8>(
      rays, state_->scene,
      [&](const int* valid, RTCIntersectContext& context, RTCRay8& query) {
        rtcOccluded8(valid, state_->scene, &context, &query);
      },
      // Embree marks an occluded lane by tfar = -inf (as rtcOccluded1, see occluded()).
      [&](std::size_t index, bool valid, const RTCRay8& query, std::size_t lane) {
        occluded_out[index] = valid && query.tfar[lane] == -std::numeric_limits<float>::infinity() ? 1 : 0;
      });
}

void EmbreeAccelerator::occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded_out,
                                 std::span<TraversalStats> stats) const {
  detail::check_batch_sizes(rays.size(), occluded_out.size(), stats.size());
  for_each_ray(rays.size(), [&](std::size_t i) { occluded_out[i] = occluded(rays[i]) ? 1 : 0; });
}

Hit EmbreeAccelerator::intersect(const QueryContext& context, const Ray& ray, std::size_t ray_index) const {
  detail::check_context_index(context, ray_index);
  require_context_filter(state_->options.context_filter);
  const Built built{state_->scene, state_->prim_ids};
  return with_context(built.prim_ids, context, ray_index,
                      [&](RTCIntersectContext& c) { return intersect_in(built, c, ray); });
}

bool EmbreeAccelerator::occluded(const QueryContext& context, const Ray& ray, std::size_t ray_index) const {
  detail::check_context_index(context, ray_index);
  require_context_filter(state_->options.context_filter);
  const Built built{state_->scene, state_->prim_ids};
  return with_context(built.prim_ids, context, ray_index,
                      [&](RTCIntersectContext& c) { return occluded_in(built, c, ray); });
}

void EmbreeAccelerator::intersect(const QueryContext& context, std::span<const Ray> rays, std::span<Hit> hits) const {
  detail::check_batch_sizes(rays.size(), hits.size(), 0);
  detail::check_context_sizes(context, rays.size());
  require_context_filter(state_->options.context_filter);
  const Built built{state_->scene, state_->prim_ids};
  for_each_ray(rays.size(), [&](std::size_t i) {
    hits[i] = with_context(built.prim_ids, context, i,
                           [&](RTCIntersectContext& c) { return intersect_in(built, c, rays[i]); });
  });
}

void EmbreeAccelerator::occluded(const QueryContext& context, std::span<const Ray> rays,
                                 std::span<std::uint8_t> occluded_out) const {
  detail::check_batch_sizes(rays.size(), occluded_out.size(), 0);
  detail::check_context_sizes(context, rays.size());
  require_context_filter(state_->options.context_filter);
  const Built built{state_->scene, state_->prim_ids};
  for_each_ray(rays.size(), [&](std::size_t i) {
    occluded_out[i] =
        with_context(built.prim_ids, context, i, [&](RTCIntersectContext& c) { return occluded_in(built, c, rays[i]); })
            ? 1
            : 0;
  });
}

std::size_t EmbreeAccelerator::memory_bytes() const {
  return state_->scene_bytes > 0 ? static_cast<std::size_t>(state_->scene_bytes) : 0;
}

std::size_t EmbreeAccelerator::input_memory_bytes(const Scene& scene) const {
  (void)scene;  // Embree reads only its own copies; the id map back to the scene's ids is the bench's, not Embree's
  return state_->vertices.size() * sizeof(float) + state_->triangles.size() * sizeof(state_->triangles[0]);
}

std::vector<BuildStatistic> EmbreeAccelerator::build_statistics() const {
  return {{"threads", static_cast<double>(state_->options.threads)},
          {"build_quality", static_cast<double>(to_embree(state_->options.quality))},
          {"robust", state_->options.robust ? 1.0 : 0.0},
          {"triangles", static_cast<double>(state_->triangles.size())}};
}

std::vector<std::string> EmbreeAccelerator::validate() const {
  const State& s = *state_;
  if (!s.scene) return {"not built"};
  std::vector<std::string> problems;
  if (!s.last_error.empty()) problems.push_back(s.last_error);
  RTCBounds bounds;
  rtcGetSceneBounds(s.scene, &bounds);
  const AABB& want = s.source->bounds();
  if (!want.is_empty() && (bounds.lower_x > want.lo.x || bounds.lower_y > want.lo.y || bounds.lower_z > want.lo.z ||
                           bounds.upper_x < want.hi.x || bounds.upper_y < want.hi.y || bounds.upper_z < want.hi.z)) {
    problems.push_back("embree scene bounds do not enclose the scene bounds");
  }
  return problems;
}

const OptionTable<EmbreeOptions>& embree_option_table() {
  using O = EmbreeOptions;
  static const OptionTable<O> table = [] {
    OptionTable<O> t("embree");
    t.choice("quality", &O::quality,
             {{"low", EmbreeBuildQuality::low}, {"medium", EmbreeBuildQuality::medium},
              {"high", EmbreeBuildQuality::high}},
             "Embree's build quality (RTC_BUILD_QUALITY_*)");
    t.boolean("robust", &O::robust, "RTC_SCENE_FLAG_ROBUST: Embree's watertight mode");
    t.boolean("filter", &O::context_filter,
              "RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION: queries with a context (skip, masks, filters) through an "
              "intersection filter");
    t.integer("threads", &O::threads, 0, 1 << 16,
              "Embree's worker threads; 0 = Embree's default (the CLI passes its --threads)");
    return t;
  }();
  return table;
}

void register_embree(std::vector<AcceleratorInfo>& registry) {
  AcceleratorInfo info = registry_entry<EmbreeAccelerator>(
      embree_option_table(), "Intel Embree 3 (found at build time), for comparisons: rtcIntersect1/8, rtcOccluded1", {});
  info.comparison = true;
  registry.push_back(std::move(info));
}

}  // namespace rayaccel

#else

namespace rayaccel {

void register_embree(std::vector<AcceleratorInfo>&) {}

}  // namespace rayaccel

#endif  // RAYACCEL_HAVE_EMBREE

namespace rayaccel {

void enable_embree_comparison() { add_registry_hook(register_embree); }

}  // namespace rayaccel
