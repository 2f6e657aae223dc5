// Octree: eight children per cell, primitives in every leaf they overlap, front-to-back parametric traversal
// (Revelles, Urena & Lastra 2000), and insertion / removal after the build.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/grid_dda.h"
#include "rayaccel/accel/option_table.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/geometry/ray_box.h"

namespace rayaccel {

struct OctreeOptions {
  int max_depth = 13;   ///< levels below the root at most (1..20); 13 resolves a 1/500 object (teapot in a stadium)
  int max_prims = 8;    ///< a leaf with more primitives splits (unless at max_depth or splitting cannot help, see
                        ///< Octree::worth_splitting)
  bool exact = true;    ///< triangles: reference only leaves the triangle overlaps (SAT)
  bool mailbox = true;  ///< skip primitives this ray tested in a recent leaf
  double pad = 0.0;     ///< the root box is the scene box grown by pad * its extent on each side (room to insert)
  std::optional<AABB> root_bounds;  ///< explicit root box instead; must hold the scene's bounds
};

struct OctreeNode {
  std::uint32_t first_child;  ///< 4 bytes: index of the first of 8 consecutive children; kLeaf for a leaf
  std::uint32_t list;         ///< 4 bytes: a leaf's index into the primitive lists; unused for an interior node
};
static_assert(sizeof(OctreeNode) == 8, "OctreeNode is 8 bytes");

/// The Octree's options: key, member, range and doc of each (the registry's options, their parsing and checks).
const OptionTable<OctreeOptions>& octree_option_table();

class Octree final : public AcceleratorImpl<Octree> {
 public:
  static constexpr std::uint32_t kLeaf = 0xFFFFFFFFu;
  static constexpr int kMaxDepth = 20;

  /// Throws Error naming the first option outside its range (octree_option_table()).
  explicit Octree(OctreeOptions options = {});

  /// Builds over every valid primitive of `scene` (all become active).
  void build(const Scene& scene) override;
  /// Adds primitive `id` of the built-over scene (e.g. one added by Scene::append_triangles) to the active set,
  /// touching only the leaves it overlaps and splitting those that grow past max_prims. Throws Error when `id` is
  /// out of range, invalid, already active, or not inside the root box (the root is never grown: build with
  /// OctreeOptions::pad or root_bounds to leave room, or rebuild).
  void insert(std::uint32_t id) override;
  /// Removes primitive `id` from the active set and merges sibling leaves whose union fits in max_prims. The
  /// primitive's geometry must be what it was at insertion. Throws Error when `id` is not active.
  void remove(std::uint32_t id) override;
  bool supports_incremental() const override { return true; }
  /// Rebuilds (a cell's references cannot be refitted: a moved triangle may enter other cells) over every valid
  /// primitive but those remove()d since the last build, which stay out.
  UpdateKind update(const Scene& scene) override;
  bool is_active(std::uint32_t id) const { return id < active_.size() && active_[id] != 0; }
  std::uint32_t active_count() const { return active_count_; }
  const AABB& root_box() const { return root_box_; }

  std::size_t memory_bytes() const override;
  std::vector<BuildStatistic> build_statistics() const override;
  std::vector<std::string> validate() const override;

  /// Child `child` (bit 0: upper x half, bit 1: y, bit 2: z) of a cell; build and traversal share it.
  static AABB child_box(const AABB& box, int child) {
    const Vec3 c = box.center();
    AABB out;
    for (int a = 0; a < 3; ++a) {
      const bool upper = (child >> a) & 1;
      out.lo[a] = upper ? c[a] : box.lo[a];
      out.hi[a] = upper ? box.hi[a] : c[a];
    }
    return out;
  }

  /// Visits cells front to back: at an interior cell, the child holding the entry point comes first and each
  /// mid-plane crossing inside the cell's [t0, t1] flips one axis (Revelles et al.; negative directions handled by
  /// the sign of the crossing, zero components by the origin's side). Stops once the closest hit lies in the current
  /// leaf (hit.t <= leaf exit).
  template <bool AnyHit, class Stats>
  void trace(const PreparedRay& ray, Hit& hit, Stats& stats) const {
    if (active_count_ == 0) return;
    if (!grid_box_is_finite(root_box_)) {  // one leaf over a box wider than float's range (see build())
      test_every_leaf<AnyHit>(ray, hit, stats);
      return;
    }
    float t0 = ray.t_min, t1 = ray.t_max;
    if (!clip_ray_to_box(ray, root_box_, t0, t1)) return;
    // The cells are ordered along the ray measured from the traversal start (see TraversalStart): t0, t1 and the
    // mid-plane crossings below are distances from start.origin, and hit.t is compared with them as distances along
    // the ray.
    const TraversalStart start(ray, root_box_, t0);
    if (!start.precise) {
      test_every_leaf<AnyHit>(ray, hit, stats);
      return;
    }
    if (start.shifted) {  // widened again for the rounding of the subtraction
      t0 = static_cast<float>(double(t0) - start.t_base);
      t1 = static_cast<float>(double(t1) - start.t_base);
      t0 *= t0 >= 0.0f ? kSlabWidenDown : kSlabWidenUp;
      t1 *= t1 >= 0.0f ? kSlabWidenUp : kSlabWidenDown;
    }
    struct Entry {
      AABB box;
      std::uint32_t node;
      float t0, t1;
    };
    Entry stack[3 * kMaxDepth + 4];
    int top = 0;
    stack[top++] = {root_box_, 0, t0, t1};
    RayMailbox<true> mailbox;
    while (top > 0) {
      const Entry e = stack[--top];
      stats.visit_node();
      const OctreeNode& n = nodes_[e.node];
      if (n.first_child == kLeaf) {
        const std::vector<std::uint32_t>& list = lists_[n.list];
        if (test_cell_primitives<AnyHit>(*scene_, list.data(), list.data() + list.size(), options_.mailbox, mailbox,
                                         ray, hit, stats)) {
          return;
        }
        if (hit.t <= start.absolute(e.t1)) return;
        continue;
      }
      const Vec3 c = e.box.center();
      int child = 0, crossings = 0;
      float cross_t[3];
      int cross_axis[3];
      for (int a = 0; a < 3; ++a) {
        if (ray.direction[a] == 0.0f || !std::isfinite(ray.inv_direction[a])) {
          child |= start.origin[a] >= c[a] ? 1 << a : 0;
          continue;
        }
        const float tm = (c[a] - start.origin[a]) * ray.inv_direction[a];
        const bool past = tm <= e.t0;  // the mid plane lies behind the entry point
        child |= (ray.direction[a] > 0.0f) == past ? 1 << a : 0;
        if (!past && tm < e.t1) {
          int k = crossings++;
          for (; k > 0 && cross_t[k - 1] > tm; --k) { cross_t[k] = cross_t[k - 1]; cross_axis[k] = cross_axis[k - 1]; }
          cross_t[k] = tm;
          cross_axis[k] = a;
        }
      }
      int order[4];
      float bounds[5];
      order[0] = child;
      bounds[0] = e.t0;
      for (int k = 0; k < crossings; ++k) {
        order[k + 1] = order[k] ^ (1 << cross_axis[k]);
        bounds[k + 1] = cross_t[k];
      }
      bounds[crossings + 1] = e.t1;
      for (int k = crossings; k >= 0; --k) {
        const std::uint32_t id = n.first_child + std::uint32_t(order[k]);
        const OctreeNode& cn = nodes_[id];
        if (cn.first_child == kLeaf && lists_[cn.list].empty()) continue;
        stack[top++] = {child_box(e.box, order[k]), id, bounds[k], bounds[k + 1]};
      }
    }
  }

 private:
  /// Tests the lists of every leaf, in any order (the traversal when TraversalStart is not precise).
  template <bool AnyHit, class Stats>
  void test_every_leaf(const PreparedRay& ray, Hit& hit, Stats& stats) const {
    std::uint32_t stack[8 * kMaxDepth + 8];
    int top = 0;
    stack[top++] = 0;
    RayMailbox<true> mailbox;
    while (top > 0) {
      const OctreeNode& n = nodes_[stack[--top]];
      stats.visit_node();
      if (n.first_child != kLeaf) {
        for (std::uint32_t c = 0; c < 8; ++c) stack[top++] = n.first_child + c;
        continue;
      }
      const std::vector<std::uint32_t>& list = lists_[n.list];
      if (test_cell_primitives<AnyHit>(*scene_, list.data(), list.data() + list.size(), options_.mailbox, mailbox,
                                       ray, hit, stats)) {
        return;
      }
    }
  }
  /// A cell may split above max_depth only while its children stay above min_cell_size (see grid_dda.h).
  bool may_split(const AABB& box, int depth) const {
    return depth < options_.max_depth && grid_box_is_finite(root_box_) &&
           max_component(box.extent()) * 0.5f >= min_cell_size(root_box_);
  }
  /// Splitting helps when some child holds some but not all of the cell's primitives, or when a single child holds
  /// them all (the cell shrinks around them). When two or more children would each hold all of them (a stack of
  /// duplicates on a large triangle, or large triangles covering the cell) it cannot: such a stack would otherwise
  /// split down to max_depth over the triangle's whole area. Nor does it help when the children would together hold
  /// more than kMaxReferenceGrowth times the cell's references (long slivers whose boxes overlap most octants):
  /// references would multiply at every level without separating anything.
  static constexpr std::size_t kMaxReferenceGrowth = 4;
  static bool worth_splitting(const std::array<std::size_t, 8>& child_counts, std::size_t count) {
    std::size_t total = 0;
    for (std::size_t c : child_counts) total += c;
    if (total > kMaxReferenceGrowth * count) return false;
    const auto occupied = std::count_if(child_counts.begin(), child_counts.end(), [](std::size_t c) { return c > 0; });
    return occupied == 1 ||
           std::any_of(child_counts.begin(), child_counts.end(), [&](std::size_t c) { return c > 0 && c < count; });
  }
  void split(std::uint32_t node, const AABB& box, int depth);
  void insert_into(std::uint32_t node, const AABB& box, int depth, std::uint32_t id);
  void remove_from(std::uint32_t node, const AABB& box, int depth, std::uint32_t id);
  void try_merge(std::uint32_t node);
  std::uint32_t new_list();
  std::uint32_t new_block();
  bool overlaps(std::uint32_t id, const AABB& box) const;
  void validate_node(std::uint32_t node, const AABB& box, int depth, std::vector<std::uint8_t>& reached,
                     std::vector<std::uint8_t>& seen, std::vector<std::string>& problems) const;

  OctreeOptions options_;
  const Scene* scene_ = nullptr;
  AABB root_box_;
  float pad_ = 0.0f;
  bool exact_used_ = false;
  std::vector<OctreeNode> nodes_;                   ///< node 0 is the root; children in blocks of 8
  std::vector<std::vector<std::uint32_t>> lists_;   ///< leaf primitive lists
  std::vector<std::uint32_t> free_blocks_;          ///< first nodes of released child blocks
  std::vector<std::uint32_t> free_lists_;           ///< released list slots
  std::vector<std::uint8_t> active_;                ///< per primitive id: in the tree
  std::vector<std::uint8_t> removed_;               ///< per primitive id: remove()d since the build (update keeps out)
  std::uint32_t active_count_ = 0;
};

void register_octree(std::vector<AcceleratorInfo>& registry);

}  // namespace rayaccel
