// Wide BVH (4 or 8 children per node, child boxes SoA, Triangle4 leaf blocks): a binary SAH tree collapsed by the least
// SAH cost (Ylitie, Karras, Laine 2017) or greedily (Wald, Benthin, Boulos 2008; Dammertz et al. 2008), traced with SSE2, AVX2 or AVX-512 lanes chosen at run time,
// closest hit near-first, any hit farthest first per ray octant; packets of eight in wide_bvh_packets.cpp (Wald 2001).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/option_table.h"
#include "rayaccel/bvh/binned_sah_builder.h"
#include "rayaccel/bvh/build_tree.h"
#include "rayaccel/core/huge_page_allocator.h"
#include "rayaccel/simd/box_kernel.h"
#include "rayaccel/simd/dispatch.h"
#include "rayaccel/simd/triangle_blocks.h"
#include "rayaccel/wide/child_push.h"
#include "rayaccel/wide/wide_node.h"

namespace rayaccel::wide {

struct BeamFrustum;  // beam_frustum.h

/// Traversal pushes at most W-1 entries per level; collapsing never adds levels to the binary tree's kBvhMaxDepth;
/// the AVX-512 pushes write eight entries at a time (child_push.h), hence the 8 more.
inline constexpr int kStackSize = 7 * kBvhMaxDepth + 8;

/// Instruction set of the eight-wide traversal. best: the best this CPU runs (simd::best_isa: AVX-512 where the CPU
/// has it, see simd/isa.h); avx2: the AVX2 kernels even on an AVX-512 CPU (so tests cover both).
enum class WideIsa { best, avx2 };

/// How the binary tree's nodes are gathered into wide nodes (wide_collapse.cpp).
enum class WideCollapse {
  area,  ///< open the child of largest surface area until W children (Wald, Benthin, Boulos 2008)
  sah,   ///< the least SAH cost over every way of gathering (Ylitie, Karras, Laine 2017's dynamic programme)
};

struct WideBvhOptions {
  /// Children per node: 4 (SSE2), 8 (AVX2), or 0 for the widest this CPU runs.
  int width = 0;
  /// Eight-wide kernels' instruction set: the best this CPU runs, or at most AVX2 (for testing that path).
  WideIsa isa = WideIsa::best;
  /// The binary tree that is collapsed: binned SAH whose leaves hold up to two Triangle4 blocks, costed per block
  /// (four triangles are tested for the price of one, so the SAH charges 1 per started block of 4, as Embree's
  /// builders do): full blocks mean fewer leaves and nodes, so less memory and faster builds for the same rays per
  /// second (BENCHMARKS.md, "Option choices").
  BinnedSahOptions binary{
      .max_leaf_size = 8, .costs = {.traversal = 1.0f, .intersection = 1.0f}, .bin_count = 16, .block_size = 4};
  /// Triangle pre-splitting before the binary build (Karras & Aila 2013, see bvh/presplit.h): extra references as a
  /// fraction of the triangle count, 0..4; 0 builds over one reference per triangle. Ignored for other primitives.
  /// 0.1 takes most of the gain on architectural scenes for a moderate build-time cost; larger fractions add build
  /// time and memory for little more (BENCHMARKS.md).
  float presplit = 0.1f;
  /// Pre-split only scenes whose presplit_potential() (bvh/presplit.h) is at least this; 0 pre-splits every triangle
  /// scene. Pre-splitting paid on Crytek Sponza and cost build time for no trace gain on scenes of low potential and
  /// on the conference room; 4 lies between the conference room and Sponza (potentials and runs: BENCHMARKS.md,
  /// "Option choices").
  float presplit_threshold = 4.0f;
  /// Spatial splits in the binary build (Stich, Friedrich & Dietrich 2009; bvh/sbvh_builder.h) with at most this
  /// fraction of extra references, 0..1; 0 builds with object splits only (after pre-splitting, above). Above 0 it
  /// replaces pre-splitting, and the binary build is the sequential SBVH builder: faster secondary rays on Crytek
  /// Sponza, slower on the conference room, builds 7-20x longer (docs/benchmark-history.md, step 33).
  float spatial = 0.0f;
  /// Rounds of insertion-based optimisation of the binary tree before the collapse (Bittner, Hapala & Havran 2013;
  /// bvh/reinsertion.h), 0..64; 0 leaves the builder's tree as it is. 16 measured 11-19% faster rays on the
  /// conference room, within noise elsewhere, for 4-37% more build time (docs/benchmark-history.md, step 34).
  std::uint32_t reinsert = 16;
  /// How the binary tree is gathered into wide nodes: by the least SAH cost, which measured faster on three of the
  /// four shared scenes and a third fewer nodes (docs/benchmark-history.md, step 31).
  WideCollapse collapse = WideCollapse::sah;
};

template <int W>
using NodeArray = std::vector<Node<W>, HugePageAllocator<Node<W>>>;

/// The wide BVH's options: key, member, range and doc of each (the registry's options, their parsing and checks).
const OptionTable<WideBvhOptions>& wide_bvh_option_table();

class WideBvh final : public AcceleratorImpl<WideBvh> {
 public:
  /// Throws Error naming the first option outside its range (wide_bvh_option_table()).
  explicit WideBvh(WideBvhOptions config = {});

  void build(const Scene& scene) override;
  /// Builds from any binary builder's tree over the scene's primitives. A tree with spatial splits may reference a
  /// primitive from several leaves (each with the box of its part); a primitive repeated within one leaf is kept once.
  void build_from(const Scene& scene, const BuildTree& tree);
  /// Refit after the scene's vertices moved (Scene::set_vertices() or buffers_changed(); same primitives): every
  /// Triangle4 copy is refreshed from the scene and every child box recomputed bottom-up (children follow their
  /// parent in the node array, so one backward pass), the tree shape kept. A tree built with pre-split references
  /// then bounds whole triangles in every leaf that holds a piece: conservative (the answers stay exact; boxes overlap
  /// more than after a rebuild). Throws Error when nothing was built or the tree refers past the scene's primitives.
  void refit();
  bool supports_refit() const override { return true; }
  /// refit() when it keeps every answer (detail::refit_covers_scene), else build(scene).
  UpdateKind update(const Scene& scene) override;
  bool supports_save() const override { return true; }
  /// Writes the nodes and Triangle4 blocks to a versioned binary file (wide_bvh_file.cpp: magic, version, width,
  /// scene fingerprint, counts, checksum), atomically. Throws Error naming the file when it cannot be written.
  void save(const std::filesystem::path& path) const override;
  /// Replaces this tree by the one in `path`, built over `scene`; checks, in order, size, magic, version, width (this
  /// CPU must run it), scene, counts, checksum, then validate(). Throws Error naming the file and the fault.
  void load(const std::filesystem::path& path, const Scene& scene) override;
  int width() const { return width_; }
  std::size_t memory_bytes() const override;
  std::vector<BuildStatistic> build_statistics() const override;
  std::vector<std::string> validate() const override;
  /// Eight rays at a time with eight-wide nodes (wide_bvh_packets.cpp); one by one with four-wide nodes or for
  /// primitives other than triangles.
  void intersect_packets(std::span<const Ray> rays, std::span<Hit> hits) const override;
  /// Any hits, eight rays at a time with eight-wide nodes (wide_bvh_packets.cpp), each ray leaving its packet once
  /// occluded; one by one where intersect_packets() is.
  void occluded_packets(std::span<const Ray> rays, std::span<std::uint8_t> occluded) const override;
  /// The packet forms under a query context: the same packet traversal, each lane's rules asked before every
  /// triangle test and the filter of every closer hit (wide_bvh_packets.cpp).
  void intersect_packets(const QueryContext& context, std::span<const Ray> rays, std::span<Hit> hits) const override;
  /// True when the packet traversals run: eight-wide nodes (AVX builds) over a non-empty triangle tree.
  bool has_packet_traversal() const;
  /// One packet of closest hits from child reference `start` instead of the root (entry points of generalized rays;
  /// see trace_from()): rays[0 .. count), count <= 8, hits into hits[0 .. count). Returns the rays whose kept hit
  /// may tie with another primitive's at the same t (the packet and intersect() keep the first they meet, in their
  /// own orders) or that the scalar kernel decided: every other ray's hit is intersect()'s bit for bit; trace those
  /// again with trace_from() where that is needed. Only where has_packet_traversal().
  int intersect_packet_from(std::uint32_t start, const Ray* rays, int count, Hit* hits) const;
  /// Up to eight packets of one beam's tile traced together from `start`, closest hits: rays[8p .. 8p + 8) is packet
  /// p (void rays fill unused lanes), count = 8 * packets <= 64, hits into hits[0 .. count). Each node's children are
  /// culled by `frustum` for the whole tile at once (it must hold every ray that is not void: BeamFrustum::holds()),
  /// then tested packet by packet; the children met are entered nearest first. `ties` gets the rays (bit i: rays[i])
  /// intersect_packet_from() would name; every other ray's hit is intersect()'s bit for bit. `prove`: the frustum is
  /// not yet known to hold the rays, so each packet's lanes are proven first (holds_in_lanes()). Returns the packets
  /// (bit p) it refused, writing nothing for them: off the packet kernels' fast path, a ray not proven inside, or
  /// direction signs other than the first packet's (trace those on their own). Only where has_packet_traversal().
  int intersect_tile_from(std::uint32_t start, const BeamFrustum& frustum, const Ray* rays, int count, Hit* hits,
                          std::uint64_t& ties, bool prove = false) const;
  void occluded_packets(const QueryContext& context, std::span<const Ray> rays,
                        std::span<std::uint8_t> occluded) const override;

  /// The queries beyond the first hit (wide_bvh_queries.cpp; see detail::StructureWithQueries): scalar walks over
  /// the same nodes and blocks.
  void find_crossings(HitList& list) const;
  void find_closest_point(ClosestPointSearch& search) const;

  template <bool AnyHit, class Stats>
  void trace(const PreparedRay& ray, Hit& hit, Stats& stats) const {
    trace_from<AnyHit>(root_, ray, hit, stats);
  }
  /// trace() started at child reference `start` (a node index, or a leaf reference) instead of the root (entry
  /// points of generalized rays): the same answer as trace() for a ray whose every possible hit lies under `start`.
  template <bool AnyHit, class Stats>
  void trace_from(std::uint32_t start, const PreparedRay& ray, Hit& hit, Stats& stats) const {
    // Eight lanes (AVX2 or its AVX-512 build) test eight-wide nodes, four SSE2 lanes four-wide ones.
    simd::run_with_lanes(isa_, [&]<class Lanes>() RAYACCEL_LANE_LAMBDA {
      if constexpr (Lanes::kWidth == 8) {
        traverse<simd::BoxKernel<Lanes>, AnyHit>(nodes8_, start, ray, hit, stats);
      } else {
        traverse<simd::BoxKernel<Lanes>, AnyHit>(nodes4_, start, ray, hit, stats);
      }
    });
  }

  /// Read access for traversals of other kinds (generalized rays): the root reference (kEmptyChild when empty),
  /// the nodes of the built width, and the primitives of a leaf reference (kInvalidPrimId marks an unused lane).
  std::uint32_t root() const { return root_; }
  const NodeArray<4>& nodes4() const { return nodes4_; }
  const NodeArray<8>& nodes8() const { return nodes8_; }
  template <class F>
  void for_each_leaf_prim(std::uint32_t leaf_ref, F&& f) const {
    const std::uint32_t first = leaf_first_block(leaf_ref), end = first + leaf_block_count(leaf_ref);
    for (std::uint32_t b = first; b < end; ++b) {
      for (std::uint32_t id : blocks_[b].prim_id) {
        if (id != kInvalidPrimId) f(id);
      }
    }
  }

 private:
  /// True when this CPU and build run eight-wide nodes (the eight-lane kernels, simd/isa.h).
  static bool runs_eight_wide();
  /// Sets width_ and isa_ for nodes `width` wide (4 or 8; 0: the widest this CPU runs): eight-wide only where
  /// runs_eight_wide(), else four-wide with the same tree shape rules; the instruction set config_.isa allows.
  void select_kernels(int width);
  template <int W>
  std::uint32_t emit(const BuildTree& tree, std::uint32_t binary_node, int depth, NodeArray<W>& nodes);
  std::uint32_t emit_leaf(const BuildTree& tree, std::uint32_t binary_node);
  /// collapse=sah: fills collapse_plan_ for the subtree of `binary_node` and slot_cost[j - 1], its least SAH cost
  /// when it takes at most j child slots of a wide node, j = 1..width_.
  void plan_collapse(const BuildTree& tree, std::uint32_t binary_node, float* slot_cost);
  /// Boxes of every binary node (children after their parent, as every builder stores them).
  static HugePageVector<AABB> binary_node_bounds(const BuildTree& tree);
  struct LeafIdCounts {
    std::uint32_t repeats = 0;     ///< further pieces of a pre-split primitive already in the leaf
  };
  /// The primitives a binary leaf contributes, each once; `dropped` counts what was left out.
  std::size_t leaf_ids(const BuildTree& tree, std::uint32_t binary_node, std::uint32_t* ids,
                       LeafIdCounts& dropped) const;
  void fill_leaves();
  template <class Kernel>
  RAYACCEL_LANE_INLINE void find_crossings_in(const NodeArray<Kernel::kWidth>& nodes, HitList& list) const;
  template <int W>
  void find_closest_point_in(const NodeArray<W>& nodes, ClosestPointSearch& search) const;
  /// Calls query.test() for every triangle of the leaf `ref`.
  template <class Query>
  void test_leaf(std::uint32_t ref, Query& query) const;
  /// Every primitive id the leaves hold (padding lanes skipped).
  std::vector<std::uint32_t> leaf_prim_ids() const;
  /// Box of the primitives a leaf reference holds, from the scene's current bounds.
  AABB leaf_box(std::uint32_t ref) const;
  template <int W>
  void refit_nodes(NodeArray<W>& nodes);
  template <int W>
  void validate_nodes(const NodeArray<W>& nodes, std::vector<std::string>& problems) const;

  /// One packet: rays[0 .. count), count <= 8, closest hits into hits[0 .. count), or with AnyHit a hit (the first
  /// found) for each occluded ray and a miss for the others (wide_bvh_packets.cpp). Context is NoPacketContext or
  /// the packet's PacketContext (src/wide/packet_context.h). kTies (closest hit only): traced from `start`, returns
  /// the rays intersect_packet_from() names; otherwise from the root, returning 0.
  template <class S>
  RAYACCEL_LANE_INLINE int trace_tile(std::uint32_t start, const BeamFrustum& frustum, const Ray* rays, int count,
                                      Hit* hits, std::uint64_t& ties, bool prove) const;
  template <class S, bool AnyHit, class Context, bool kTies = false>
  RAYACCEL_LANE_INLINE int trace_packet(const Ray* rays, int count, Hit* hits, Context& context,
                                        std::uint32_t start = kEmptyChild) const;
  /// Asks for the four cache lines of a child met by the box test (an inner node's 256 bytes, or a leaf's first
  /// blocks) before it is visited, as Embree's traversal does: incoherent rays spend most of their time waiting for
  /// nodes, and the children pushed now are popped after the memory has had time to answer.
  template <int W>
  RAYACCEL_LANE_INLINE static void prefetch_child(const Node<W>* nodes, const simd::Triangle4* blocks,
                                                  std::uint32_t ref) {
    prefetch_four_lines((ref & kLeafBit) ? reinterpret_cast<const char*>(blocks + leaf_first_block(ref))
                                         : reinterpret_cast<const char*>(nodes + ref));
  }
  /// prefetch_child without a branch on the leaf bit: both addresses are computed and one is chosen by a mask (the
  /// other is never dereferenced). The any-hit traversal's loop over every child met uses it, where the leaf bit of
  /// each child is data the branch predictor cannot learn (docs/benchmark-history.md, step 36); the closest-hit
  /// traversal keeps the branch, not measured with this form.
  template <int W>
  RAYACCEL_LANE_INLINE static void prefetch_child_unbranched(const Node<W>* nodes, const simd::Triangle4* blocks,
                                                             std::uint32_t ref) {
    const auto leaf = reinterpret_cast<std::uintptr_t>(blocks) +
                      std::uintptr_t{leaf_first_block(ref)} * sizeof(simd::Triangle4);
    const auto inner = reinterpret_cast<std::uintptr_t>(nodes) + std::uintptr_t{ref & ~kLeafBit} * sizeof(Node<W>);
    static_assert(kLeafBit == 1u << 31, "the leaf bit is the top bit");
    const std::uintptr_t is_leaf = std::uintptr_t{0} - std::uintptr_t{ref >> 31};  // all ones for a leaf
    prefetch_four_lines(reinterpret_cast<const char*>((leaf & is_leaf) | (inner & ~is_leaf)));
  }
  RAYACCEL_LANE_INLINE static void prefetch_four_lines(const char* p) {
    __builtin_prefetch(p);
    __builtin_prefetch(p + 64);
    __builtin_prefetch(p + 128);
    __builtin_prefetch(p + 192);
  }
  /// Closest hit: children near-first by their entry distances (below); any hit: in the node's order for the ray's
  /// octant, leaving at the first hit (wide/any_hit_traversal.h).
  template <class Kernel, bool AnyHit, class Stats>
  RAYACCEL_LANE_INLINE void traverse(const NodeArray<Kernel::kWidth>& nodes, std::uint32_t start,
                                     const PreparedRay& ray, Hit& hit, Stats& stats) const {
    if constexpr (AnyHit) {
      traverse_any_hit<Kernel>(nodes, start, ray, hit, stats);
    } else {
      traverse_closest<Kernel>(nodes, start, ray, hit, stats);
    }
  }
  template <class Kernel, class Stats>
  RAYACCEL_LANE_INLINE void traverse_closest(const NodeArray<Kernel::kWidth>& nodes, std::uint32_t start,
                                             const PreparedRay& ray, Hit& hit, Stats& stats) const;
  template <class Kernel, class Stats>
  RAYACCEL_LANE_INLINE void traverse_any_hit(const NodeArray<Kernel::kWidth>& nodes, std::uint32_t start,
                                             const PreparedRay& ray, Hit& hit, Stats& stats) const;
  template <class Lanes, bool AnyHit, class Stats>
  RAYACCEL_LANE_INLINE bool intersect_leaf(std::uint32_t ref, const simd::Triangle4* blocks,
                                           const simd::TrianglePacket<Lanes>& packet, const PreparedRay& ray,
                                           Hit& hit, Stats& stats) const;
  /// The leaf test of scenes other than triangle meshes (blocks hold only ids: Scene::intersect one by one), kept out
  /// of line so the triangle traversal's loop holds no call that would take its registers.
  template <bool AnyHit, class Stats>
  [[gnu::noinline, gnu::cold]] bool intersect_leaf_prims(std::uint32_t ref, const PreparedRay& ray, Hit& hit,
                                                         Stats& stats) const;

  WideBvhOptions config_;
  int width_ = 4;
  simd::Isa isa_ = simd::Isa::sse2;  ///< width 8: avx2 or avx512; width 4: sse2
  const Scene* scene_ = nullptr;
  bool triangles_ = true;  ///< false: blocks hold only ids, tested through Scene::intersect
  // Large arrays on transparent huge pages where the system has them (fewer page faults and TLB misses).
  NodeArray<4> nodes4_;
  NodeArray<8> nodes8_;
  /// Every lane written by fill_leaves.
  std::vector<simd::Triangle4, UninitializedHugePageAllocator<simd::Triangle4>> blocks_;
  std::uint32_t block_count_ = 0;  ///< build-time only: blocks reserved by emit_leaf, allocated after emit
  std::uint32_t root_ = kEmptyChild;
  HugePageVector<AABB> binary_bounds_;  ///< build-time only: box of each binary node
  /// Build-time only, collapse=sah: per binary node, 4 bits for each j = 2..8: the slots its left child's subtree
  /// takes when the node is opened into j slots, 0 when it takes one slot itself.
  HugePageVector<std::uint32_t> collapse_plan_;
  struct PendingLeaf {
    std::uint32_t first_id, id_count;  ///< the leaf's primitives: pending_ids_[first_id .. first_id + id_count)
    std::uint32_t first_block;
  };
  HugePageVector<PendingLeaf> pending_leaves_;  ///< build-time only: leaves whose blocks fill_leaves() writes
  HugePageVector<std::uint32_t> pending_ids_;  ///< build-time only: primitives of the pending leaves
  int depth_ = 0;
  bool spatial_splits_ = false;         ///< built from a tree with spatial splits: validate() allows repeats
  std::uint32_t references_ = 0;        ///< references of the binary tree
  std::uint32_t split_triangles_ = 0;   ///< triangles pre-split into several references
  double presplit_potential_ = 0.0;     ///< build(): presplit_potential() of the scene (0 for other kinds)
  std::uint32_t dropped_repeats_ = 0;   ///< references dropped because their primitive was already in the leaf
};

/// Tests a leaf's blocks (`blocks` is blocks_.data(), held by the traversal): two at a time when Lanes is eight wide
/// (AVX2), one at a time with SSE otherwise.
template <class Lanes, bool AnyHit, class Stats>
RAYACCEL_LANE_INLINE bool WideBvh::intersect_leaf(std::uint32_t ref, const simd::Triangle4* blocks,
                                                  const simd::TrianglePacket<Lanes>& packet, const PreparedRay& ray,
                                                  Hit& hit, Stats& stats) const {
  if (!triangles_) [[unlikely]] return intersect_leaf_prims<AnyHit>(ref, ray, hit, stats);
  simd::BlockMailbox unused;  // no mailbox: a primitive is in one leaf, or once per leaf (pre-split pieces)
  return simd::intersect_block_run<Lanes, AnyHit, false>(packet, ray, blocks + leaf_first_block(ref),
                                                         leaf_block_count(ref), unused, hit, stats);
}

template <bool AnyHit, class Stats>
bool WideBvh::intersect_leaf_prims(std::uint32_t ref, const PreparedRay& ray, Hit& hit, Stats& stats) const {
  bool found = false;
  const std::uint32_t end = leaf_first_block(ref) + leaf_block_count(ref);
  for (std::uint32_t b = leaf_first_block(ref); b < end; ++b) {
    for (std::uint32_t id : blocks_[b].prim_id) {
      if (id == kInvalidPrimId) continue;
      found |= test_scene_primitive(*scene_, id, ray, hit, stats);
      if (AnyHit && found) return true;
    }
  }
  return found;
}

template <class Kernel, class Stats>
RAYACCEL_LANE_INLINE void WideBvh::traverse_closest(const NodeArray<Kernel::kWidth>& nodes, std::uint32_t start,
                                                     const PreparedRay& ray, Hit& hit, Stats& stats) const {
  constexpr int W = Kernel::kWidth;
  if (start == kEmptyChild) return;
  // The arrays' addresses in locals: read through the vectors, they would be reloaded at every step, as the stores
  // to the stack and the hit might change them for all the compiler knows.
  const Node<W>* const node_at = nodes.data();
  const simd::Triangle4* const blocks = blocks_.data();
  const simd::TrianglePacket<typename Kernel::Lanes> triangle_packet(ray);
  const typename Kernel::Packet box_packet = Kernel::prepare(ray);
  // AVX-512 lanes (simd::Avx8Masked) push the children met without a branch per child (child_push.h).
  constexpr bool kMaskedPush = requires { requires Kernel::Lanes::kMaskRegisters; };
  std::uint32_t ref = start;
  // Closest hit: children near-first, each stack entry with its entry distance, culled on pop by the closest hit.
  using Entry = StackEntry;
  Entry stack[kStackSize];
  int top = 0;
  for (;;) {
    stats.visit_node();
    if (ref & kLeafBit) {
      intersect_leaf<typename Kernel::Lanes, false>(ref, blocks, triangle_packet, ray, hit, stats);
    } else {
      const Node<W>& node = node_at[ref];
      typename Kernel::F entry_lanes;
      unsigned mask = Kernel::intersect_lanes(box_packet, node, hit.t, entry_lanes);
      alignas(32) float entry[W];
      Kernel::Lanes::store(entry, entry_lanes);
      if (mask) {
        // The common cases first (Wald et al. 2008 on wide-BVH traversal order): one child met is entered
        // without touching the stack; of two, the farther is pushed; only three or more are sorted.
        const int first = __builtin_ctz(static_cast<unsigned>(mask));
        mask &= mask - 1;
        if (mask == 0) {
          ref = node.child[first];
          prefetch_child(node_at, blocks, ref);
          continue;
        }
        const int second = __builtin_ctz(static_cast<unsigned>(mask));
        mask &= mask - 1;
        if (mask == 0) {
          const bool first_nearer = !(entry[second] < entry[first]);
          const int near = first_nearer ? first : second;
          const int far = first_nearer ? second : first;
          stack[top++] = {node.child[far], entry[far]};
          ref = node.child[near];
          prefetch_child(node_at, blocks, ref);
          prefetch_child(node_at, blocks, node.child[far]);
          continue;
        }
        if constexpr (kMaskedPush) {
          for (unsigned m = mask; m; m &= m - 1) prefetch_child(node_at, blocks, node.child[__builtin_ctz(m)]);
          prefetch_child(node_at, blocks, node.child[first]);
          prefetch_child(node_at, blocks, node.child[second]);
          ref = push_sorted<typename Kernel::Lanes>(node, mask | 1u << first | 1u << second, entry_lanes, stack,
                                                    top);
          continue;
        }
        // Three or more: pushed in place and sorted there farthest first (insertion sort: at most W entries);
        // the nearest is taken straight back off the top. Gathering them elsewhere and copying cost a memcpy.
        Entry* met = stack + top;
        met[0] = {node.child[first], entry[first]};
        met[1] = {node.child[second], entry[second]};
        prefetch_child(node_at, blocks, met[0].ref);
        prefetch_child(node_at, blocks, met[1].ref);
        if (met[0].t_entry < met[1].t_entry) std::swap(met[0], met[1]);
        int n = 2;
        for (; mask; mask &= mask - 1) {
          const int lane = __builtin_ctz(static_cast<unsigned>(mask));
          const Entry e{node.child[lane], entry[lane]};
          prefetch_child(node_at, blocks, e.ref);
          int i = n++;
          for (; i > 0 && met[i - 1].t_entry < e.t_entry; --i) met[i] = met[i - 1];
          met[i] = e;
        }
        top += n - 1;
        ref = met[n - 1].ref;
        continue;
      }
    }
    // Pop the next subtree whose entry is not beyond the closest hit so far.
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

}  // namespace rayaccel::wide

#include "rayaccel/wide/any_hit_traversal.h"  // IWYU pragma: export
