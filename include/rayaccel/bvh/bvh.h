// Bvh<BV>: a bounding volume hierarchy over any BoundingVolume (AABB, sphere, OBB, k-DOP). A builder makes the tree
// shape from PrimRefs; volumes are then fitted per node; traversal runs over a flat depth-first array of nodes,
// nearer child first by entry distance, with a fixed-size stack bounded by the build-time depth limit.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/option_table.h"
#include "rayaccel/bv/aabb_volume.h"
#include "rayaccel/bv/bounding_volume.h"
#include "rayaccel/bvh/binary_traversal.h"
#include "rayaccel/bvh/build_tree.h"
#include "rayaccel/bvh/sbvh_builder.h"
#include "rayaccel/scene/scene.h"
#include "rayaccel/geometry/clip_polygon.h"
#include "rayaccel/geometry/ray_triangle.h"

namespace rayaccel {

enum class BvhBuilder { binned, sweep, sbvh, lbvh, ploc };
/// Registry name of a builder: "binned", "sweep", "sbvh", "lbvh", "ploc".
const char* to_string(BvhBuilder builder);

struct BvhOptions {
  BvhBuilder builder = BvhBuilder::binned;
  std::uint32_t max_leaf_size = 4;          ///< most primitives per leaf, 1..255
  SahCosts costs;                           ///< SAH constants for the builders and the reported cost (1 and 1)
  std::uint32_t bin_count = 16;             ///< bins per axis of the binned SAH and SBVH builders
  float max_growth = 1.3f;                  ///< SBVH: references may grow to this multiple of the primitive count
  float overlap_alpha = 1e-5f;              ///< SBVH: spatial splits are tried when the object split's children
                                            ///< overlap by more than this fraction of the root's area (Stich's alpha)
  std::uint32_t ploc_radius = 16;           ///< PLOC: neighbours searched on each side in Morton order
  std::uint32_t parallel_threshold = 4096;  ///< top-down builders: subtrees at least this large build in parallel
};

/// The options of every Bvh<BV> (all but the volume, which is its type): key, member, range and doc of each; the
/// "bvh" registry entry's options, their parsing, and the check Bvh's constructor runs.
const OptionTable<BvhOptions>& bvh_option_table();

/// Runs the configured builder over the scene's references. SBVH clips triangles to split planes; for other
/// primitive kinds it makes object splits only.
BuildTree build_bvh_shape(const Scene& scene, const BvhOptions& config);

/// Node of the flat depth-first array. Children of an interior node: the next node and nodes[index].
template <BoundingVolume BV>
struct BvhNode {
  BV volume;             // sizeof(BV) bytes (24 for AABB): encloses every primitive part in the subtree
  std::uint32_t index;   // 4 bytes: interior: index of the second child; leaf: first primitive slot
  std::uint32_t count;   // 4 bytes: leaf: number of primitive slots (>= 1); interior: 0
  bool is_leaf() const { return count > 0; }
};
static_assert(sizeof(BvhNode<AabbVolume>) == 32, "an AABB BVH node is 32 bytes: two per cache line");

struct BvhTestAccess;

template <BoundingVolume BV>
class Bvh final : public AcceleratorImpl<Bvh<BV>> {
 public:
  using Node = BvhNode<BV>;

  /// Checks the configuration (throws Error naming a bad value).
  explicit Bvh(BvhOptions config = {});

  void build(const Scene& scene) override;
  // refit() to load(): the same Accelerator members WideBvh declares, each structure with its own implementation.
  /// Re-fits every volume bottom-up after Scene::set_vertices() changed positions but not topology. The tree shape
  /// is kept; SBVH trees then bound whole primitives (their clipped parts no longer apply: a conservative refit, with
  /// more overlap than a rebuild). Throws Error when the scene's primitive count changed or nothing was built.
  void refit();
  bool supports_refit() const override { return true; }
  /// refit() when it keeps every answer (detail::refit_covers_scene), else build(scene).
  UpdateKind update(const Scene& scene) override;
  bool supports_save() const override { return true; }
  /// Writes the built tree to a versioned binary file (magic, version, volume kind, primitive count, scene
  /// fingerprint, counts, checksum). Throws Error naming the file when it cannot be written.
  void save(const std::filesystem::path& path) const override;
  /// Replaces this tree by the one in `path`, built over `scene`. Throws Error naming the file and the fault for a
  /// missing, truncated, foreign, wrong-version, wrong-volume, corrupted or wrong-scene file.
  void load(const std::filesystem::path& path, const Scene& scene) override;

  std::size_t memory_bytes() const override;
  std::vector<BuildStatistic> build_statistics() const override { return statistics_; }
  std::vector<std::string> validate() const override;

  /// The one traversal: closest hit (nearer child first) or, with AnyHit, the first hit found.
  template <bool AnyHit, class Stats>
  void trace(const PreparedRay& ray, Hit& hit, Stats& stats) const {
    trace_from<AnyHit>(0, ray, hit, stats);
  }
  /// trace() started at node `start` instead of the root (entry points of generalized rays): the same answer as
  /// trace() for a ray whose every possible hit lies in start's subtree, as nodes outside it change nothing.
  template <bool AnyHit, class Stats>
  void trace_from(std::uint32_t start, const PreparedRay& ray, Hit& hit, Stats& stats) const {
    if (nodes_.empty()) return;
    if (triangles_.empty()) {
      trace_nodes<AnyHit, false>(start, ray, hit, stats);
    } else {
      trace_nodes<AnyHit, true>(start, ray, hit, stats);
    }
  }

  /// The queries beyond the first hit (bvh_queries.h; see detail::StructureWithQueries).
  void find_crossings(HitList& list) const;
  void find_closest_point(ClosestPointSearch& search) const;

  const BvhOptions& options() const { return config_; }
  const std::vector<Node>& nodes() const { return nodes_; }
  /// The scene's primitive id held by leaf slot `slot` (a leaf holds slots [index, index + count)).
  std::uint32_t slot_prim_id(std::uint32_t slot) const { return prim_ids_[slot]; }
  /// Levels of the tree (0 when empty); never more than kBvhMaxDepth.
  int depth() const { return depth_; }

 private:
  friend struct BvhTestAccess;

  /// Flattened: every volume and triangle test is inlined into the loop (GCC otherwise keeps the slab test out of
  /// line, a call per child visited).
  template <bool AnyHit, bool Triangles, class Stats>
  [[gnu::flatten]] void trace_nodes(std::uint32_t start, const PreparedRay& ray, Hit& hit, Stats& stats) const;

  void flatten(const BuildTree& tree);
  /// Points whose hull encloses the part of a primitive one slot covers; returns their count.
  int slot_points(std::uint32_t slot, ClippedPolygon& out) const;
  /// Box of the hull points of slots [begin, end).
  AABB slot_box(std::uint32_t begin, std::uint32_t end) const;
  void copy_triangles();
  void fit_volumes();
  void compute_statistics(double build_ms);

  BvhOptions config_;
  const Scene* scene_ = nullptr;
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> prim_ids_;         ///< per slot: the scene's primitive id
  std::vector<std::array<Vec3, 3>> triangles_;  ///< per slot, triangle scenes only: the vertices, in leaf order
  std::vector<AABB> part_bounds_;               ///< per slot, SBVH only: box of the part of the primitive covered
  bool spatial_splits_ = false;                 ///< a primitive may be referenced by several leaves (SBVH)
  std::vector<BuildStatistic> statistics_;
  int depth_ = 0;
};

/// Far bound for culling volumes. A primitive test's t carries rounding far beyond the slab test's: when the ray
/// starts near a triangle's plane, the watertight test's t can be off by several 1e-6 relative. Volumes are culled
/// against hit.t widened by 2^-12 relative, so a primitive whose exact t ties the current hit is still tested and the
/// result matches brute force.
inline float bvh_cull_bound(float t) { return t + std::fabs(t) * 0x1p-12f; }

template <BoundingVolume BV>
template <bool AnyHit, bool Triangles, class Stats>
void Bvh<BV>::trace_nodes(std::uint32_t start, const PreparedRay& ray, Hit& hit, Stats& stats) const {
  const typename BV::RayContext context = BV::prepare(ray);
  traverse_binary_bvh<AnyHit>(
      nodes_.data(), start, ray.t_min,
      [&](const Node& node, float t_far, float* t_entry) {
        return node.volume.intersect(context, ray.t_min, t_far, t_entry);
      },
      [&](const Node& node) {
        for (std::uint32_t slot = node.index, end = node.index + node.count; slot < end; ++slot) {
          bool found;
          if constexpr (Triangles) {
            stats.test_primitive();
            const auto& v = triangles_[slot];
            found = test_candidate(stats, prim_ids_[slot], hit, [&](Hit& h) {
              return intersect_triangle(ray, v[0], v[1], v[2], prim_ids_[slot], h);
            });
          } else {
            found = test_scene_primitive(*scene_, prim_ids_[slot], ray, hit, stats);
          }
          if (AnyHit && found) return true;
        }
        return false;
      },
      [&] { return bvh_cull_bound(hit.t); }, stats);
}

}  // namespace rayaccel

// Member definitions of Bvh<BV>, one concern per header.
#include "rayaccel/bvh/bvh_fit.h"
#include "rayaccel/bvh/bvh_io.h"
#include "rayaccel/bvh/bvh_queries.h"
#include "rayaccel/bvh/bvh_validate.h"
