// Four-wide BVH for triangle meshes: a binary SAH tree collapsed greedily by opening the child of largest surface
// area (Wald, Benthin, Boulos 2008, "Getting rid of packets"; Dammertz et al. 2008, "Shallow bounding volume
// hierarchies"), child boxes stored SoA so one SSE test covers four children, and leaves of Triangle4 blocks tested
// four at a time with the watertight kernel (other primitive kinds: the same tree, leaves tested one by one). Closest-hit traversal visits children near-first; any-hit stops at the
// first hit.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/bvh/binned_sah_builder.h"
#include "rayaccel/bvh/build_tree.h"
#include "rayaccel/wide/simd_kernels.h"

namespace rayaccel::wide {

/// One node: the boxes of up to four children and a reference to each.
struct alignas(64) Node4 {
  float bounds[3][2][4];   ///< 96 bytes: [axis][lo, hi][child]; an unused child has lo = +inf, hi = -inf
  std::uint32_t child[4];  ///< 16 bytes: node index, or kLeafBit | first block << kBlockShift | (blocks - 1)
  std::uint32_t padding[4];  ///< 16 bytes: pads the node to two cache-line halves
};
static_assert(sizeof(Node4) == 128, "Node4 is 128 bytes");

inline constexpr std::uint32_t kLeafBit = 0x80000000u;
inline constexpr std::uint32_t kBlockShift = 3;               ///< low 3 bits: block count - 1
inline constexpr std::uint32_t kMaxLeafBlocks = 8;            ///< at most 32 triangles per leaf
inline constexpr std::uint32_t kEmptyChild = 0xFFFFFFFFu;     ///< never followed: its box is empty
inline constexpr int kStackSize = 3 * kBvhMaxDepth + 4;       ///< at most 3 pushes per level

struct WideBvhConfig {
  /// The binary tree that is collapsed: binned SAH with leaves of at most 4 triangles (one Triangle4 block). A
  /// primitive test costs 0.3 of a node visit here because four triangles are tested for the price of about one.
  BinnedSahConfig binary{.max_leaf_size = 4, .costs = {.traversal = 1.0f, .intersection = 0.3f}};
};

class WideBvh4 final : public AcceleratorImpl<WideBvh4> {
 public:
  explicit WideBvh4(WideBvhConfig config = {}) : config_(config) {}

  void build(const Scene& scene) override;
  /// Builds from any binary builder's tree over the scene's triangles (no spatial splits).
  void build_from(const Scene& scene, const BuildTree& tree);
  std::size_t memory_bytes() const override;
  std::vector<BuildStatistic> build_statistics() const override;
  std::vector<std::string> validate() const override;

  template <bool AnyHit, class Stats>
  void trace(const PreparedRay& ray, Hit& hit, Stats& stats) const;

 private:
  std::uint32_t emit(const BuildTree& tree, std::uint32_t binary_node, int depth);
  std::uint32_t emit_leaf(const BuildTree& tree, std::uint32_t binary_node);

  WideBvhConfig config_;
  const Scene* scene_ = nullptr;
  bool triangles_ = true;  ///< false: blocks hold only ids, tested through Scene::intersect
  std::vector<Node4> nodes_;
  std::vector<Triangle4> blocks_;
  std::uint32_t root_ = kEmptyChild;
  std::vector<AABB> binary_bounds_;  ///< build-time only: box of each binary node
  int depth_ = 0;
  std::uint32_t skipped_degenerate_ = 0;
};

template <bool AnyHit, class Stats>
void WideBvh4::trace(const PreparedRay& ray, Hit& hit, Stats& stats) const {
  if (root_ == kEmptyChild) return;
  const RayPacket4 packet(ray);
  struct Entry {
    std::uint32_t ref;
    float t_entry;
  };
  Entry stack[kStackSize];
  int top = 0;
  std::uint32_t ref = root_;
  for (;;) {
    if (ref & kLeafBit) {
      stats.visit_node();
      const std::uint32_t first = (ref & ~kLeafBit) >> kBlockShift;
      const std::uint32_t count = (ref & ((1u << kBlockShift) - 1)) + 1;
      for (std::uint32_t b = first; b < first + count; ++b) {
        if (triangles_) {
          stats.test_primitive(4);
          if (intersect_triangles4(packet, ray, blocks_[b], hit) && AnyHit) return;
        } else {
          for (std::uint32_t id : blocks_[b].prim_id) {
            if (id == kInvalidPrimId) continue;
            stats.test_primitive();
            if (scene_->intersect(id, ray, hit) && AnyHit) return;
          }
        }
      }
    } else {
      stats.visit_node();
      const Node4& node = nodes_[ref];
      __m128 t_entry;
      int mask = intersect_boxes4(packet, node.bounds, _mm_set1_ps(hit.t), t_entry);
      if (mask) {
        alignas(16) float entry[4];
        _mm_store_ps(entry, t_entry);
        // Collect the hit children, then push all but the nearest (farthest pushed first) and descend into it.
        Entry hits[4];
        int n = 0;
        for (; mask; mask &= mask - 1) {
          const int lane = __builtin_ctz(static_cast<unsigned>(mask));
          Entry e{node.child[lane], entry[lane]};
          int i = n++;
          if constexpr (!AnyHit) {
            for (; i > 0 && hits[i - 1].t_entry < e.t_entry; --i) hits[i] = hits[i - 1];
          }
          hits[i] = e;
        }
        for (int i = 0; i < n - 1; ++i) stack[top++] = hits[i];
        ref = hits[n - 1].ref;
        continue;
      }
    }
    // Pop the next subtree whose entry is not beyond the closest hit found so far.
    for (;;) {
      if (top == 0) return;
      const Entry& e = stack[--top];
      if (!(e.t_entry > hit.t)) {
        ref = e.ref;
        break;
      }
    }
  }
}

void register_wide_bvh(std::vector<AcceleratorInfo>& registry);

}  // namespace rayaccel::wide
