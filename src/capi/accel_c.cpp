// The C API's structures: built by registry spec over a C scene; closest-hit and any-hit queries for one ray, batches
// and packets, with or without a query context, with hits reported as (geometry id, primitive within the geometry).
#include <cstring>
#include <vector>

#include "capi_handles.h"
#include "rayaccel/accel/registry.h"

using rayaccel::capi::Failure;
using rayaccel::capi::guarded;
using rayaccel::capi::require;

namespace {

static_assert(sizeof(rayaccel_ray) == sizeof(rayaccel::Ray), "rayaccel_ray is the 32-byte Ray record");
static_assert(sizeof(rayaccel_hit) == 20, "rayaccel_hit is five 32-bit fields");

rayaccel::Ray to_ray(const rayaccel_ray& r) {
  rayaccel::Ray ray;
  ray.origin = rayaccel::Vec3{r.org_x, r.org_y, r.org_z};
  ray.t_min = r.t_min;
  ray.direction = rayaccel::Vec3{r.dir_x, r.dir_y, r.dir_z};
  ray.t_max = r.t_max;
  return ray;
}

std::vector<rayaccel::Ray> to_rays(const rayaccel_ray* rays, size_t count) {
  std::vector<rayaccel::Ray> out(count);
  for (size_t i = 0; i < count; ++i) out[i] = to_ray(rays[i]);
  return out;
}

rayaccel_hit to_hit(const rayaccel::Hit& hit, const rayaccel::GeometryTable& table) {
  // A miss maps to RAYACCEL_INVALID_ID twice (geometry_of and local_primitive of kInvalidPrimId).
  return rayaccel_hit{hit.t, table.local_primitive(hit.prim_id), hit.u, hit.v, table.geometry_of(hit.prim_id)};
}

void check_batch(const rayaccel_accel* accel, const rayaccel_ray* rays, size_t count, const void* out) {
  require(accel, "accel");
  if (count > 0) {
    require(rays, "rays");
    require(out, "output array");
  }
}

template <class Trace>
void trace_hits(const rayaccel_accel* accel, const rayaccel_ray* rays, size_t count, rayaccel_hit* out, Trace trace) {
  check_batch(accel, rays, count, out);
  const std::vector<rayaccel::Ray> in = to_rays(rays, count);
  std::vector<rayaccel::Hit> hits(count);
  trace(*accel->structure, std::span<const rayaccel::Ray>(in), std::span<rayaccel::Hit>(hits));
  const rayaccel::GeometryTable& table = accel->scene->geometries;
  for (size_t i = 0; i < count; ++i) out[i] = to_hit(hits[i], table);
}

template <class Trace>
void trace_occluded(const rayaccel_accel* accel, const rayaccel_ray* rays, size_t count, uint8_t* out, Trace trace) {
  check_batch(accel, rays, count, out);
  const std::vector<rayaccel::Ray> in = to_rays(rays, count);
  trace(*accel->structure, std::span<const rayaccel::Ray>(in), std::span<std::uint8_t>(out, count));
}

/// A rayaccel_query_context as the library's QueryContext over `count` rays: (geometry, primitive) skips turned into
/// scene-wide ids, the scene's geometry masks, and the C filter behind a trampoline that reports local ids.
class CContext {
 public:
  CContext(const rayaccel_accel& accel, const rayaccel_query_context* c, size_t count)
      : table_(accel.scene->geometries), filter_(c ? c->filter : nullptr), data_(c ? c->filter_data : nullptr) {
    context_.geometry_starts = table_.starts();
    context_.geometry_mask = accel.scene->masks;
    if (!c) return;
    if ((c->skip_geom_id == nullptr) != (c->skip_prim_id == nullptr)) {
      throw Failure{RAYACCEL_INVALID_ARGUMENT, "skip_geom_id and skip_prim_id go together (both set or both null)"};
    }
    if (count > 0 && c->skip_prim_id) {
      skip_.resize(count);
      for (size_t i = 0; i < count; ++i) {
        const uint32_t g = c->skip_geom_id[i], p = c->skip_prim_id[i];
        skip_[i] = g < table_.geometry_count() && p < table_.primitive_count(g) ? table_.first_primitive(g) + p
                                                                                 : rayaccel::kInvalidPrimId;
      }
      context_.skip_primitive = skip_;
    }
    if (count > 0 && c->skip_geometry) context_.skip_geometry = {c->skip_geometry, count};
    if (count > 0 && c->ray_mask) context_.ray_mask = {c->ray_mask, count};
    if (filter_) {
      context_.filter = [](void* self, const rayaccel::HitCandidate& h) {
        const auto& me = *static_cast<const CContext*>(self);
        const rayaccel_candidate candidate{h.geom_id, me.table_.local_primitive(h.prim_id), h.t, h.u, h.v,
                                           h.ray_index};
        return me.filter_(me.data_, &candidate) != 0;
      };
      context_.filter_data = this;
    }
  }
  CContext(const CContext&) = delete;
  const rayaccel::QueryContext& context() const { return context_; }

 private:
  const rayaccel::GeometryTable& table_;
  rayaccel_filter filter_;
  void* data_;
  std::vector<std::uint32_t> skip_;
  rayaccel::QueryContext context_;
};

}  // namespace

namespace {

/// Runs `trace(query_context)` for one of the *_context entry points, guarded like every call of the C API.
template <class Trace>
rayaccel_status with_context(const char* name, const rayaccel_accel* accel, const rayaccel_query_context* context,
                             size_t count, Trace trace) {
  return guarded(name, [&] {
    require(accel, "accel");
    const CContext c(*accel, context, count);
    trace(c.context());
  });
}

}  // namespace

extern "C" rayaccel_status rayaccel_intersect_context(const rayaccel_accel* accel,
                                                      const rayaccel_query_context* context, const rayaccel_ray* rays,
                                                      size_t count, rayaccel_hit* hits) {
  return with_context("rayaccel_intersect_context", accel, context, count, [&](const rayaccel::QueryContext& q) {
    trace_hits(accel, rays, count, hits,
               [&](const rayaccel::Accelerator& a, auto in, auto out) { a.intersect(q, in, out); });
  });
}

extern "C" rayaccel_status rayaccel_occluded_context(const rayaccel_accel* accel,
                                                     const rayaccel_query_context* context, const rayaccel_ray* rays,
                                                     size_t count, uint8_t* occluded) {
  return with_context("rayaccel_occluded_context", accel, context, count, [&](const rayaccel::QueryContext& q) {
    trace_occluded(accel, rays, count, occluded,
                   [&](const rayaccel::Accelerator& a, auto in, auto out) { a.occluded(q, in, out); });
  });
}

extern "C" rayaccel_status rayaccel_intersect_packets_context(const rayaccel_accel* accel,
                                                              const rayaccel_query_context* context,
                                                              const rayaccel_ray* rays, size_t count,
                                                              rayaccel_hit* hits) {
  return with_context("rayaccel_intersect_packets_context", accel, context, count,
                      [&](const rayaccel::QueryContext& q) {
                        trace_hits(accel, rays, count, hits, [&](const rayaccel::Accelerator& a, auto in, auto out) {
                          a.intersect_packets(q, in, out);
                        });
                      });
}

extern "C" rayaccel_status rayaccel_occluded_packets_context(const rayaccel_accel* accel,
                                                             const rayaccel_query_context* context,
                                                             const rayaccel_ray* rays, size_t count,
                                                             uint8_t* occluded) {
  return with_context("rayaccel_occluded_packets_context", accel, context, count,
                      [&](const rayaccel::QueryContext& q) {
                        trace_occluded(accel, rays, count, occluded,
                                       [&](const rayaccel::Accelerator& a, auto in, auto out) {
                                         a.occluded_packets(q, in, out);
                                       });
                      });
}

extern "C" rayaccel_status rayaccel_accel_new(rayaccel_scene* scene, const char* spec, rayaccel_accel** out) {
  return guarded("rayaccel_accel_new", [&] {
    require(scene, "scene");
    require(spec, "spec");
    require(out, "out");
    *out = nullptr;
    auto& state = *scene->state;
    {
      const std::lock_guard lock(state.mutex);
      if (!state.scene) {
        rayaccel::GeometryTable table;
        state.scene.emplace(rayaccel::scene_from_meshes(state.meshes, table, "c_api"));
        state.geometries = std::move(table);  // the same ids add_mesh recorded
        state.meshes.clear();
        state.meshes.shrink_to_fit();
      }
    }
    auto accel = std::make_unique<rayaccel_accel>();
    accel->scene = scene->state;
    accel->structure = rayaccel::make_accelerator(spec);
    accel->structure->build(*state.scene);
    *out = accel.release();
  });
}

extern "C" void rayaccel_accel_release(rayaccel_accel* accel) { delete accel; }

extern "C" rayaccel_status rayaccel_intersect1(const rayaccel_accel* accel, const rayaccel_ray* ray,
                                               rayaccel_hit* hit) {
  return guarded("rayaccel_intersect1", [&] {
    require(accel, "accel");
    require(ray, "ray");
    require(hit, "hit");
    *hit = to_hit(accel->structure->intersect(to_ray(*ray)), accel->scene->geometries);
  });
}

extern "C" rayaccel_status rayaccel_occluded1(const rayaccel_accel* accel, const rayaccel_ray* ray, int* occluded) {
  return guarded("rayaccel_occluded1", [&] {
    require(accel, "accel");
    require(ray, "ray");
    require(occluded, "occluded");
    *occluded = accel->structure->occluded(to_ray(*ray)) ? 1 : 0;
  });
}

extern "C" rayaccel_status rayaccel_intersect(const rayaccel_accel* accel, const rayaccel_ray* rays, size_t count,
                                              rayaccel_hit* hits) {
  return guarded("rayaccel_intersect", [&] {
    trace_hits(accel, rays, count, hits, [](const rayaccel::Accelerator& a, auto in, auto out) { a.intersect(in, out); });
  });
}

extern "C" rayaccel_status rayaccel_occluded(const rayaccel_accel* accel, const rayaccel_ray* rays, size_t count,
                                             uint8_t* occluded) {
  return guarded("rayaccel_occluded", [&] {
    trace_occluded(accel, rays, count, occluded,
                   [](const rayaccel::Accelerator& a, auto in, auto out) { a.occluded(in, out); });
  });
}

extern "C" rayaccel_status rayaccel_intersect_packets(const rayaccel_accel* accel, const rayaccel_ray* rays,
                                                      size_t count, rayaccel_hit* hits) {
  return guarded("rayaccel_intersect_packets", [&] {
    trace_hits(accel, rays, count, hits,
               [](const rayaccel::Accelerator& a, auto in, auto out) { a.intersect_packets(in, out); });
  });
}

extern "C" rayaccel_status rayaccel_occluded_packets(const rayaccel_accel* accel, const rayaccel_ray* rays,
                                                     size_t count, uint8_t* occluded) {
  return guarded("rayaccel_occluded_packets", [&] {
    trace_occluded(accel, rays, count, occluded,
                   [](const rayaccel::Accelerator& a, auto in, auto out) { a.occluded_packets(in, out); });
  });
}
