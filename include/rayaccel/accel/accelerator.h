// Accelerator: the one runtime interface over every structure, and AcceleratorImpl, which derives all of it from a
// structure's single templated traversal: one indirect call per ray or per batch, none per node.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "rayaccel/accel/closest_point_search.h"
#include "rayaccel/accel/hit_list.h"
#include "rayaccel/accel/leaf_test.h"
#include "rayaccel/core/hit.h"
#include "rayaccel/core/query_context.h"
#include "rayaccel/core/ray.h"
#include "rayaccel/scene/scene.h"
#include "rayaccel/core/stats.h"

namespace rayaccel {

/// What Accelerator::update() did: refitted (tree shape kept, bounds and leaf copies refreshed from the moved vertices)
/// or rebuilt from scratch.
enum class UpdateKind { refitted, rebuilt };
/// "refitted" or "rebuilt".
const char* to_string(UpdateKind kind);

/// A named figure a structure reports about its build (SAH cost, references per primitive, depth, ...).
struct BuildStatistic {
  std::string name;
  double value = 0.0;
};

class Accelerator {
 public:
  virtual ~Accelerator() = default;

  /// The registry spec this instance was made from, e.g. "bvh:bv=obb,builder=ploc".
  const std::string& spec() const { return spec_; }
  void set_spec(std::string spec) { spec_ = std::move(spec); }

  /// Builds (or rebuilds) over `scene`, which must outlive this object and stay at the same address.
  virtual void build(const Scene& scene) = 0;

  /// Closest hit with ray.t_min < t <= ray.t_max; a miss has prim_id == kInvalidPrimId and t = +inf.
  virtual Hit intersect(const Ray& ray) const = 0;
  virtual Hit intersect(const Ray& ray, TraversalStats& stats) const = 0;
  /// True when anything is hit with ray.t_min < t <= ray.t_max; stops at the first hit found.
  virtual bool occluded(const Ray& ray) const = 0;
  virtual bool occluded(const Ray& ray, TraversalStats& stats) const = 0;

  /// Parallel batches. `stats`, when not empty, receives one record per ray (for heat maps); it must then have
  /// rays.size() entries.
  virtual void intersect(std::span<const Ray> rays, std::span<Hit> hits, std::span<TraversalStats> stats = {}) const = 0;
  virtual void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                        std::span<TraversalStats> stats = {}) const = 0;

  /// Closest hits of a batch of coherent rays (camera rays of neighbouring pixels, say), with the contract of
  /// intersect(rays, hits): structures with a packet traversal (bvh_wide's eight-wide nodes) trace each run of eight
  /// consecutive rays, rays[8k .. 8k + 8), together, sharing node fetches and testing one child box against all
  /// eight rays at once; the others trace the rays one by one. Any rays may share a packet (incoherent ones only cost
  /// speed), and every answer is a closest hit, as from intersect() (a tie in t may name another primitive).
  virtual void intersect_packets(std::span<const Ray> rays, std::span<Hit> hits) const { intersect(rays, hits); }
  /// Any hits of a batch of coherent rays (shadow rays of neighbouring pixels to one light, say), with the contract of
  /// occluded(rays, occluded): 1 when anything is hit with t_min < t <= t_max, else 0. Structures with a packet
  /// traversal trace each run of eight consecutive rays together, a ray leaving its packet once it is found occluded;
  /// the others trace the rays one by one.
  virtual void occluded_packets(std::span<const Ray> rays, std::span<std::uint8_t> occluded) const {
    this->occluded(rays, occluded);
  }

  // Queries under a QueryContext (core/query_context.h): a primitive and a geometry to skip, ray and geometry masks,
  // per-primitive switches and a hit filter, all honoured in the leaves (the first three before the exact test). The
  // single-ray forms read entry `ray_index` of the context's per-ray arrays (and tell the filter that index); the
  // batches read entry i for rays[i], and throw Error when a non-empty per-ray array's size is not rays.size(). Every
  // structure of rayaccel answers them; one that cannot (a wrapped library without the support) throws Error naming
  // itself rather than ignore the context.
  virtual Hit intersect(const QueryContext& context, const Ray& ray, std::size_t ray_index = 0) const;
  virtual bool occluded(const QueryContext& context, const Ray& ray, std::size_t ray_index = 0) const;
  virtual void intersect(const QueryContext& context, std::span<const Ray> rays, std::span<Hit> hits) const;
  virtual void occluded(const QueryContext& context, std::span<const Ray> rays,
                        std::span<std::uint8_t> occluded) const;
  /// The packet forms under a context, with the answers of the batch forms above: bvh_wide's packet traversal asks
  /// each lane's rules of every triangle before its test (and the filter of each closer hit); the other structures
  /// trace the rays one by one, as their plain packet forms do.
  virtual void intersect_packets(const QueryContext& context, std::span<const Ray> rays, std::span<Hit> hits) const {
    intersect(context, rays, hits);
  }
  virtual void occluded_packets(const QueryContext& context, std::span<const Ray> rays,
                                std::span<std::uint8_t> occluded) const {
    this->occluded(context, rays, occluded);
  }

  // Queries beyond the first hit, on triangle scenes, for the structures whose traversal can enumerate every
  // candidate of a ray or search near a point (supports_queries(): brute force, the BVH family, bvh_wide). The others,
  // and scenes of spheres or user primitives, throw Error naming the structure or the scene kind.

  /// True when all_hits(), count_hits() and closest_point() are implemented (for triangle scenes).
  virtual bool supports_queries() const { return false; }
  /// Every crossing of the surface with ray.t_min < t <= ray.t_max, sorted by t (equal t: by primitive id), the
  /// `max_hits` nearest written to `hits` (resized to them). A ray through an edge or vertex of a closed mesh crosses
  /// it there once (geometry/crossing.h: one of the triangles met there counts, by simulation of simplicity), or,
  /// touching it without crossing, zero or two times; so a ray from outside to outside always crosses a closed mesh an
  /// even number of times. Every hit is exactly the one intersect() would report for its triangle alone. Returns the
  /// number of crossings (before trimming to max_hits). A void ray (see PreparedRay) has none.
  virtual std::size_t all_hits(const Ray& ray, std::vector<Hit>& hits,
                               std::size_t max_hits = std::numeric_limits<std::size_t>::max()) const;
  /// all_hits() without the hits: the number of crossings.
  virtual std::size_t count_hits(const Ray& ray) const;
  /// The closest point of the scene to `point` within `max_distance` (branch and bound over the structure). Throws
  /// Error for a non-finite point or a max_distance that is NaN or negative.
  virtual ClosestPoint closest_point(const Vec3& point,
                                     float max_distance = std::numeric_limits<float>::infinity()) const;
  /// Parallel batches of count_hits() and closest_point(); sizes must match (Error otherwise).
  void count_hits(std::span<const Ray> rays, std::span<std::uint32_t> counts) const;
  void closest_points(std::span<const Vec3> points, std::span<ClosestPoint> out,
                      float max_distance = std::numeric_limits<float>::infinity()) const;

  // Changes after the build. Every structure answers update(); the others below are supported where the matching
  // supports_*() says so, and otherwise throw Error naming the structure.

  /// True when update() can refit in place instead of rebuilding (the BVH family and bvh_wide).
  virtual bool supports_refit() const { return false; }
  /// Brings the structure up to date with `scene` after its vertex positions moved (Scene::set_vertices(), or
  /// Scene::buffers_changed() after writing the caller's buffers), with the answers a fresh build(scene) would give.
  /// Structures with supports_refit() refit: the tree shape is kept and every bound and leaf copy of the vertices is
  /// recomputed (cheap, but the tree's quality decays as the motion grows; rebuild now and then). They rebuild
  /// instead when `scene` is not the one built over, its primitive count changed, or a primitive left out of the
  /// build (invalid or zero-area then) is now valid. The others rebuild. Returns which happened.
  virtual UpdateKind update(const Scene& scene) {
    build(scene);
    return UpdateKind::rebuilt;
  }

  /// True when insert() and remove() work (the octree): primitives enter and leave the built structure one by one.
  virtual bool supports_incremental() const { return false; }
  /// Adds primitive `prim_id` of the built-over scene (e.g. one appended by Scene::append_triangles()).
  virtual void insert(std::uint32_t prim_id);
  /// Removes primitive `prim_id`; queries no longer see it.
  virtual void remove(std::uint32_t prim_id);

  /// True when save() and load() work (the BVH family and bvh_wide).
  virtual bool supports_save() const { return false; }
  /// Writes the built structure to `path` (atomically: a reader never sees half a file) in a versioned binary
  /// format that records the scene it was built over. Throws Error naming the file when it cannot be written.
  virtual void save(const std::filesystem::path& path) const;
  /// Replaces this structure by the one saved in `path`, which must have been built over `scene` (same primitives,
  /// same geometry). Throws Error naming the file and the fault for a missing, truncated, foreign, wrong-version,
  /// wrong-kind, corrupted or stale (other scene) file; this object stays usable after a failed load.
  virtual void load(const std::filesystem::path& path, const Scene& scene);

  /// Bytes of the structure's own data (the scene's arrays are not counted).
  virtual std::size_t memory_bytes() const = 0;
  /// Bytes of input that queries read besides memory_bytes(), for `scene` (the one built over): the Scene's
  /// arrays for rayaccel's structures; for a wrapped library, the geometry buffers it was handed. The sum of the
  /// two is what answering queries holds, and compares libraries on the same terms.
  virtual std::size_t input_memory_bytes(const Scene& scene) const { return scene.memory_bytes(); }
  /// Figures about the last build; may be empty.
  virtual std::vector<BuildStatistic> build_statistics() const { return {}; }
  /// Checks the structure's invariants; returns one line per violation (empty when valid).
  virtual std::vector<std::string> validate() const = 0;

 private:
  std::string spec_;
};

namespace detail {
/// Runs body(begin, end) over [0, count) in parallel chunks (TBB), every chunk in the calling thread's floating-point
/// environment (see accelerator.cpp); the one place batches are split.
void parallel_for_rays(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body);
/// Rays per packet of intersect_packets() and occluded_packets().
inline constexpr std::size_t kPacketSize = 8;
/// parallel_for_rays() for packet batches: body(begin, end) gets ray ranges that start at a multiple of
/// kPacketSize and end at one or at `count`, so no packet is split between chunks.
void parallel_for_packets(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body);
void check_batch_sizes(std::size_t rays, std::size_t outputs, std::size_t stats);
/// Throws Error unless every per-ray array of `context` is empty or has `rays` entries (naming the array).
void check_context_sizes(const QueryContext& context, std::size_t rays);
/// Throws Error unless every non-empty per-ray array of `context` has an entry `ray_index`.
void check_context_index(const QueryContext& context, std::size_t ray_index);
/// Throws Error naming `accel`'s spec: it cannot honour a query context.
[[noreturn]] void refuse_context(const Accelerator& accel);
/// Throws Error unless `point` is finite and max_distance >= 0 (naming the bad value).
void check_point_query(const Vec3& point, float max_distance);
/// For update(): true when a refit of a structure that holds the primitives `ids` (repeats allowed) keeps every answer
/// on `scene`: every id is in range and every valid primitive of the scene is among them. False, so the structure must
/// rebuild, when the scene grew or a primitive left out of the build (invalid or zero-area then) is now valid.
bool refit_covers_scene(const Scene& scene, std::span<const std::uint32_t> ids);
/// Throws Error, naming `query` and the scene's kind, unless `scene` is a triangle scene.
void require_triangle_scene(const Scene& scene, const char* query);

/// A structure that answers the queries beyond the first hit, with the members
///   void find_crossings(HitList& list) const;              // list.test() every triangle the ray may cross
///   void find_closest_point(ClosestPointSearch& s) const;  // branch and bound: s.test() the triangles near enough
/// (each throws Error, through require_triangle_scene, for a scene that is not made of triangles).
template <class S>
concept StructureWithQueries = requires(const S& s, HitList& list, ClosestPointSearch& search) {
  s.find_crossings(list);
  s.find_closest_point(search);
};
}  // namespace detail

/// Implements the Accelerator interface from one member of Derived:
///   template <bool AnyHit, class Stats> void trace(const PreparedRay& ray, Hit& hit, Stats& stats) const;
/// `hit` arrives as Hit::begin(ray); trace() shrinks hit.t with each closer hit, and with AnyHit may return at
/// the first hit. Stats is TraversalStats or NoStats.
template <class Derived>
class AcceleratorImpl : public Accelerator {
 public:
  Hit intersect(const Ray& ray) const final {
    NoStats stats;
    return trace_one<false>(ray, stats);
  }
  Hit intersect(const Ray& ray, TraversalStats& stats) const final { return trace_one<false>(ray, stats); }
  bool occluded(const Ray& ray) const final {
    NoStats stats;
    return trace_one<true>(ray, stats).found();
  }
  bool occluded(const Ray& ray, TraversalStats& stats) const final { return trace_one<true>(ray, stats).found(); }

  void intersect(std::span<const Ray> rays, std::span<Hit> hits, std::span<TraversalStats> stats = {}) const final;
  void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                std::span<TraversalStats> stats = {}) const final;

  // Under a query context: the same traversal, its Stats a ContextStats that every leaf consults.
  Hit intersect(const QueryContext& context, const Ray& ray, std::size_t ray_index = 0) const final {
    detail::check_context_index(context, ray_index);
    return trace_in_context<false>(context, ray, ray_index);
  }
  bool occluded(const QueryContext& context, const Ray& ray, std::size_t ray_index = 0) const final {
    detail::check_context_index(context, ray_index);
    return trace_in_context<true>(context, ray, ray_index).found();
  }
  void intersect(const QueryContext& context, std::span<const Ray> rays, std::span<Hit> hits) const final {
    detail::check_batch_sizes(rays.size(), hits.size(), 0);
    detail::check_context_sizes(context, rays.size());
    detail::parallel_for_rays(rays.size(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) hits[i] = trace_in_context<false>(context, rays[i], i);
    });
  }
  void occluded(const QueryContext& context, std::span<const Ray> rays,
                std::span<std::uint8_t> occluded) const final {
    detail::check_batch_sizes(rays.size(), occluded.size(), 0);
    detail::check_context_sizes(context, rays.size());
    detail::parallel_for_rays(rays.size(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) occluded[i] = trace_in_context<true>(context, rays[i], i).found();
    });
  }

  // The queries beyond the first hit, for a Derived with the members of detail::StructureWithQueries.
  using Accelerator::count_hits;  // the batch form, which this class's count_hits(ray) would hide
  bool supports_queries() const final { return detail::StructureWithQueries<Derived>; }
  std::size_t all_hits(const Ray& ray, std::vector<Hit>& hits, std::size_t max_hits) const final {
    if constexpr (detail::StructureWithQueries<Derived>) {
      const PreparedRay prepared(ray);
      HitList list(prepared, hits);
      if (!prepared.is_void()) static_cast<const Derived*>(this)->find_crossings(list);
      return list.finish(max_hits);
    } else {
      return Accelerator::all_hits(ray, hits, max_hits);
    }
  }
  std::size_t count_hits(const Ray& ray) const final {
    thread_local std::vector<Hit> scratch;
    return all_hits(ray, scratch, 0);
  }
  ClosestPoint closest_point(const Vec3& point, float max_distance) const final {
    if constexpr (detail::StructureWithQueries<Derived>) {
      detail::check_point_query(point, max_distance);
      ClosestPointSearch search(point, max_distance);
      static_cast<const Derived*>(this)->find_closest_point(search);
      return search.result();
    } else {
      return Accelerator::closest_point(point, max_distance);
    }
  }

 private:
  template <bool AnyHit>
  Hit trace_in_context(const QueryContext& context, const Ray& ray, std::size_t ray_index) const {
    NoStats none;
    ContextStats<NoStats> stats(context, ray_index, none);
    return trace_one<AnyHit>(ray, stats);
  }
  template <bool AnyHit, class Stats>
  Hit trace_one(const Ray& ray, Stats& stats) const {
    const PreparedRay prepared(ray);
    Hit hit = Hit::begin(prepared);
    if (!prepared.is_void()) static_cast<const Derived*>(this)->template trace<AnyHit>(prepared, hit, stats);
    hit.finish();
    return hit;
  }
};


template <class Derived>
void AcceleratorImpl<Derived>::intersect(std::span<const Ray> rays, std::span<Hit> hits,
                                         std::span<TraversalStats> stats) const {
  detail::check_batch_sizes(rays.size(), hits.size(), stats.size());
  detail::parallel_for_rays(rays.size(), [&](std::size_t begin, std::size_t end) {
    if (stats.empty()) {
      NoStats none;
      for (std::size_t i = begin; i < end; ++i) hits[i] = trace_one<false>(rays[i], none);
    } else {
      for (std::size_t i = begin; i < end; ++i) hits[i] = trace_one<false>(rays[i], stats[i]);
    }
  });
}

template <class Derived>
void AcceleratorImpl<Derived>::occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                                        std::span<TraversalStats> stats) const {
  detail::check_batch_sizes(rays.size(), occluded.size(), stats.size());
  detail::parallel_for_rays(rays.size(), [&](std::size_t begin, std::size_t end) {
    if (stats.empty()) {
      NoStats none;
      for (std::size_t i = begin; i < end; ++i) occluded[i] = trace_one<true>(rays[i], none).found() ? 1 : 0;
    } else {
      for (std::size_t i = begin; i < end; ++i) occluded[i] = trace_one<true>(rays[i], stats[i]).found() ? 1 : 0;
    }
  });
}

}  // namespace rayaccel
