// Wide BVH: collapse of a binary tree into 4- or 8-wide nodes, Triangle4 leaf packing, validation, registration.
#include "rayaccel/wide/wide_bvh.h"

#include <algorithm>
#include <array>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "rayaccel/bvh/presplit.h"
#include "rayaccel/core/error.h"

namespace rayaccel::wide {

namespace {

template <int W>
void set_child_bounds(Node<W>& node, int lane, const AABB& box) {
  for (int a = 0; a < 3; ++a) {
    node.bounds[a][0][lane] = box.lo[a];
    node.bounds[a][1][lane] = box.hi[a];
  }
}

template <int W>
AABB child_bounds(const Node<W>& node, int lane) {
  AABB box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = node.bounds[a][0][lane];
    box.hi[a] = node.bounds[a][1][lane];
  }
  return box;
}

/// Boxes of every binary node; BuildTree stores children after their parent, so one backward pass suffices.
HugePageVector<AABB> binary_node_bounds(const BuildTree& tree) {
  HugePageVector<AABB> boxes(tree.nodes.size());
  for (std::size_t i = tree.nodes.size(); i-- > 0;) {
    const BuildNode& n = tree.nodes[i];
    if (n.is_leaf()) {
      if (std::size_t{n.first} + n.count > tree.refs.size()) {
        throw Error("wide BVH: binary tree leaf " + std::to_string(i) + " references past the end of the tree's " +
                    std::to_string(tree.refs.size()) + " references");
      }
      for (std::uint32_t r = n.first; r < n.first + n.count; ++r) boxes[i].extend(tree.refs[r].bounds);
    } else {
      // Children after their parent (as every builder stores them): the backward pass has their boxes already.
      if (n.first <= i || std::size_t{n.first} + 1 >= tree.nodes.size()) {
        throw Error("wide BVH: binary tree node " + std::to_string(i) + " has children at " +
                    std::to_string(n.first) + ", not after it within the tree's " +
                    std::to_string(tree.nodes.size()) + " nodes");
      }
      boxes[i] = merge(boxes[n.first], boxes[n.first + 1]);
    }
  }
  return boxes;
}

}  // namespace

bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

bool cpu_has_avx512() {
  static const bool has = cpu_has_avx2() && __builtin_cpu_supports("avx512f") &&
                          __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq") &&
                          __builtin_cpu_supports("avx512bw");
  return has;
}

std::size_t WideBvh::leaf_ids(const BuildTree& tree, std::uint32_t binary_node, std::uint32_t* ids,
                              LeafIdCounts& dropped) const {
  const BuildNode& n = tree.nodes[binary_node];
  std::size_t count = 0;
  dropped = {};
  for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
    const std::uint32_t id = tree.refs[i].prim_id;
    if (triangles_ && coincident_[id]) {
      ++dropped.coincident;
      continue;
    }
    // Pieces of one split primitive in one leaf: test it once.
    if (tree.spatial_splits && std::find(ids, ids + count, id) != ids + count) {
      ++dropped.repeats;
      continue;
    }
    ids[count++] = id;
  }
  return count;
}

std::uint32_t WideBvh::emit_leaf(const BuildTree& tree, std::uint32_t binary_node) {
  const BuildNode& n = tree.nodes[binary_node];
  if (n.count > 4 * kMaxLeafBlocks) {
    throw Error("wide BVH: a binary leaf holds " + std::to_string(n.count) + " primitives, more than the " +
                std::to_string(4 * kMaxLeafBlocks) + " a wide leaf can take");
  }
  std::array<std::uint32_t, 4 * kMaxLeafBlocks> ids;
  LeafIdCounts dropped;
  const std::size_t count = leaf_ids(tree, binary_node, ids.data(), dropped);
  skipped_degenerate_ += dropped.coincident;
  dropped_repeats_ += dropped.repeats;
  if (count == 0) return kEmptyChild;
  // Blocks are reserved here and filled later in parallel (fill_leaves), where the random reads of the scene's
  // vertices are spread over the threads.
  const auto block_count = static_cast<std::uint32_t>((count + 3) / 4);
  const std::uint32_t first_block = block_count_;
  block_count_ += block_count;
  pending_leaves_.push_back({static_cast<std::uint32_t>(pending_ids_.size()), static_cast<std::uint32_t>(count),
                             first_block});
  pending_ids_.insert(pending_ids_.end(), ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(count));
  return kLeafBit | (first_block << kBlockShift) | (block_count - 1);
}

void WideBvh::fill_leaves() {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pending_leaves_.size(), 512),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t k = range.begin(); k != range.end(); ++k) {
                        const PendingLeaf& leaf = pending_leaves_[k];
                        const std::uint32_t* ids = pending_ids_.data() + leaf.first_id;
                        const std::size_t count = leaf.id_count;
                        for (std::size_t i = 0; i < (count + 3) / 4 * 4; ++i) {
                          Triangle4& block = blocks_[leaf.first_block + i / 4];
                          const int lane = static_cast<int>(i % 4);
                          if (i < count && triangles_) {
                            set_block_lane(block, lane, *scene_, ids[i]);
                            continue;
                          }
                          // Padding (a zero triangle, never hit), or only an id for other primitive kinds.
                          block.prim_id[lane] = i < count ? ids[i] : kInvalidPrimId;
                          for (int v = 0; v < 3; ++v) {
                            for (int a = 0; a < 3; ++a) block.vertex[v][a][lane] = 0.0f;
                          }
                        }
                      }
                    });
}

template <int W>
std::uint32_t WideBvh::emit(const BuildTree& tree, std::uint32_t binary_node, int depth, NodeArray<W>& nodes) {
  depth_ = std::max(depth_, depth);
  if (tree.nodes[binary_node].is_leaf()) return emit_leaf(tree, binary_node);
  // Open the inner child of largest surface area until W children are gathered.
  // Leaves take area -1 so that they are never opened.
  std::array<std::uint32_t, W> children{tree.nodes[binary_node].first, tree.nodes[binary_node].first + 1};
  std::array<float, W> areas{};
  const auto openable_area = [&](std::uint32_t c) {
    return tree.nodes[c].is_leaf() ? -1.0f : binary_bounds_[c].surface_area();
  };
  areas[0] = openable_area(children[0]);
  areas[1] = openable_area(children[1]);
  int child_count = 2;
  while (child_count < W) {
    int best = -1;
    float best_area = -1.0f;
    for (int i = 0; i < child_count; ++i) {
      if (areas[i] > best_area) {
        best = i;
        best_area = areas[i];
      }
    }
    if (best < 0) break;
    const std::uint32_t opened = tree.nodes[children[best]].first;
    children[best] = opened;
    areas[best] = openable_area(opened);
    children[child_count] = opened + 1;
    areas[child_count++] = openable_area(opened + 1);
  }
  const auto index = static_cast<std::uint32_t>(nodes.size());
  nodes.emplace_back();
  Node<W> node{};
  for (int lane = 0; lane < W; ++lane) {
    node.child[lane] = kEmptyChild;
    set_child_bounds(node, lane, AABB::empty());
  }
  int lane = 0;
  for (int i = 0; i < child_count; ++i) {
    const std::uint32_t c = children[i];
    const std::uint32_t ref = emit<W>(tree, c, depth + 1, nodes);
    if (ref == kEmptyChild) continue;
    node.child[lane] = ref;
    set_child_bounds(node, lane, binary_bounds_[c]);
    ++lane;
  }
  nodes[index] = node;
  return lane == 0 ? kEmptyChild : index;
}

void WideBvh::build(const Scene& scene) {
  // Computed for every triangle scene (1-2 ms on the shared scenes), so the statistic is reported whatever the options.
  const bool triangles = scene.kind() == PrimitiveKind::triangles;
  const double potential = triangles ? presplit_potential(scene) : 0.0;
  if (config_.presplit > 0.0f && triangles && potential >= config_.presplit_threshold) {
    PresplitResult presplit = presplit_references(scene, {.fraction = config_.presplit});
    BuildTree tree = build_binned_sah(std::move(presplit.refs), config_.binary);
    tree.spatial_splits = true;
    build_from(scene, tree);
    split_triangles_ = presplit.split_triangles;
  } else {
    build_from(scene, build_binned_sah(scene.build_references(), config_.binary));
  }
  presplit_potential_ = potential;
}

void WideBvh::build_from(const Scene& scene, const BuildTree& tree) {
  scene_ = &scene;
  spatial_splits_ = tree.spatial_splits;
  references_ = static_cast<std::uint32_t>(tree.refs.size());
  split_triangles_ = 0;
  presplit_potential_ = 0.0;  // build() sets it; a tree built elsewhere was not chosen by it
  dropped_repeats_ = 0;
  triangles_ = scene.kind() == PrimitiveKind::triangles;
  width_ = config_.width == 8 || (config_.width == 0 && cpu_has_avx2()) ? 8 : 4;
  if (width_ == 8 && !cpu_has_avx2()) width_ = 4;  // width=8 asked on a CPU without AVX2: same tree shape rules, SSE
  avx512_ = width_ == 8 && config_.isa != WideIsa::avx2 && cpu_has_avx512();
  nodes4_.clear();
  nodes8_.clear();
  blocks_.clear();
  block_count_ = 0;
  depth_ = 0;
  skipped_degenerate_ = 0;
  binary_bounds_ = binary_node_bounds(tree);
  coincident_.assign(triangles_ ? scene.primitive_count() : 0, 0);
  if (triangles_) {
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, scene.primitive_count(), 4096),
                      [&](const tbb::blocked_range<std::uint32_t>& range) {
                        for (std::uint32_t id = range.begin(); id != range.end(); ++id) {
                          coincident_[id] = scene.is_valid(id) && coincident_vertices(scene.triangle(id)) ? 1 : 0;
                        }
                      });
  }
  pending_leaves_.clear();
  pending_ids_.clear();
  pending_ids_.reserve(tree.refs.size());
  // Room for the nodes without regrowing: every wide node takes at least one binary interior node, so their count
  // bounds it. Full eight-wide nodes would need a seventh of that, but the shared scenes need 1/3.5 to 1/3.3 (many
  // children are leaves, which are not opened), so the old estimate of a seventh always regrew, copying the whole
  // array into fresh pages. Capacity that is never written is never given pages.
  // Leaf blocks are counted during the collapse and allocated once after it.
  const std::size_t interior = tree.nodes.size() / 2 + 1;
  if (width_ == 8) {
    nodes8_.reserve(interior);
  } else {
    nodes4_.reserve(interior);
  }
  if (tree.nodes.empty()) {
    root_ = kEmptyChild;
  } else {
    root_ = width_ == 8 ? emit<8>(tree, 0, 1, nodes8_) : emit<4>(tree, 0, 1, nodes4_);
  }
  blocks_.resize(block_count_);  // uninitialized: fill_leaves() writes every lane of every block, in parallel
  fill_leaves();
  binary_bounds_ = {};
  coincident_ = {};
  pending_leaves_ = {};
  pending_ids_ = {};
  if (depth_ > kBvhMaxDepth) {
    throw Error("wide BVH: tree depth " + std::to_string(depth_) + " exceeds the traversal stack bound");
  }
}

std::size_t WideBvh::memory_bytes() const {
  return nodes4_.size() * sizeof(Node<4>) + nodes8_.size() * sizeof(Node<8>) + blocks_.size() * sizeof(Triangle4);
}

std::vector<BuildStatistic> WideBvh::build_statistics() const {
  std::size_t used_lanes = 0;
  for (const auto& b : blocks_) {
    for (std::uint32_t id : b.prim_id) used_lanes += id != kInvalidPrimId ? 1 : 0;
  }
  return {{"width", double(width_)},
          {"avx512_kernels", avx512_ ? 1.0 : 0.0},
          {"nodes", double(nodes4_.size() + nodes8_.size())},
          {"triangle4_blocks", double(blocks_.size())},
          {"block_fill", blocks_.empty() ? 0.0 : double(used_lanes) / (4.0 * blocks_.size())},
          {"depth", double(depth_)},
          {"skipped_coincident_vertex_triangles", double(skipped_degenerate_)},
          {"references", double(references_)},
          {"presplit_triangles", double(split_triangles_)},
          {"presplit_potential", presplit_potential_},
          {"leaf_repeats_dropped", double(dropped_repeats_)}};
}

template <int W>
void WideBvh::validate_nodes(const NodeArray<W>& nodes, std::vector<std::string>& problems) const {
  std::vector<std::uint8_t> seen(scene_->primitive_count(), 0);
  struct Item {
    std::uint32_t ref;
    AABB box;
    int depth;
  };
  std::vector<Item> pending;
  if (root_ != kEmptyChild) pending.push_back({root_, scene_->bounds(), 1});
  while (!pending.empty() && problems.size() < 20) {
    const Item item = pending.back();
    pending.pop_back();
    if (item.depth > kBvhMaxDepth) problems.push_back("depth exceeds the traversal stack bound");
    if (item.ref & kLeafBit) {
      const std::uint32_t first = leaf_first_block(item.ref);
      const std::uint32_t count = leaf_block_count(item.ref);
      if (first + count > blocks_.size()) {
        problems.push_back("leaf block range out of bounds");
        continue;
      }
      for (std::uint32_t b = first; b < first + count; ++b) {
        for (int lane = 0; lane < 4; ++lane) {
          const std::uint32_t id = blocks_[b].prim_id[lane];
          if (id == kInvalidPrimId) continue;
          if (id >= seen.size()) {
            problems.push_back("leaf references primitive " + std::to_string(id) + " outside the scene");
            continue;
          }
          if (spatial_splits_) {
            // Spatial splits: a primitive may sit in several leaves, each holding a part of it, but once per leaf;
            // the leaf box bounds only the parts, so it must meet the primitive's box rather than contain it.
            const std::size_t before = std::size_t(b - first) * 4 + std::size_t(lane);  // lanes before this one
            bool repeated = false;
            for (std::size_t k = 0; k < before && !repeated; ++k) {
              repeated = blocks_[first + k / 4].prim_id[k % 4] == id;
            }
            if (repeated) problems.push_back("primitive " + std::to_string(id) + " appears twice in one leaf");
            seen[id] = 1;
            if (!item.box.overlaps(scene_->primitive_bounds(id))) {
              problems.push_back("primitive " + std::to_string(id) + " does not meet its leaf box");
            }
          } else {
            if (seen[id]++) problems.push_back("primitive " + std::to_string(id) + " referenced twice");
            if (!item.box.contains(scene_->primitive_bounds(id))) {
              problems.push_back("primitive " + std::to_string(id) + " lies outside its leaf box");
            }
          }
          if (triangles_) {
            const auto& tri = scene_->triangle(id);
            for (int v = 0; v < 3; ++v) {
              for (int a = 0; a < 3; ++a) {
                if (blocks_[b].vertex[v][a][lane] != tri[v][a]) {
                  problems.push_back("leaf copy of triangle " + std::to_string(id) + " differs from the scene");
                }
              }
            }
          }
        }
      }
      continue;
    }
    if (item.ref >= nodes.size()) {
      problems.push_back("child reference " + std::to_string(item.ref) + " out of range");
      continue;
    }
    const Node<W>& node = nodes[item.ref];
    for (int lane = 0; lane < W; ++lane) {
      if (node.child[lane] == kEmptyChild) {
        if (!child_bounds(node, lane).is_empty()) problems.push_back("unused child slot with a non-empty box");
        continue;
      }
      const AABB box = child_bounds(node, lane);
      if (!item.box.contains(box)) problems.push_back("child box outside its parent box");
      pending.push_back({node.child[lane], box, item.depth + 1});
    }
  }
  for (std::uint32_t id = 0; id < seen.size() && problems.size() < 20; ++id) {
    if (scene_->is_valid(id) && !seen[id] && !(triangles_ && coincident_vertices(scene_->triangle(id)))) {
      problems.push_back("primitive " + std::to_string(id) + " is not reachable");
    }
  }
}

std::vector<std::string> WideBvh::validate() const {
  if (!scene_) return {"not built"};
  std::vector<std::string> problems;
  if (width_ == 8) {
    validate_nodes(nodes8_, problems);
  } else {
    validate_nodes(nodes4_, problems);
  }
  return problems;
}

/// Defaults of the registry's presplit options: WideBvhConfig's defaults, written as option strings.
constexpr const char* kDefaultPresplit = "0.1";
constexpr const char* kDefaultPresplitThreshold = "4";

void register_wide_bvh(std::vector<AcceleratorInfo>& registry) {
  const BinnedSahConfig defaults = WideBvhConfig{}.binary;
  registry.push_back(
      {"bvh_wide",
       "4- or 8-wide SIMD BVH (SoA child boxes, Triangle4 leaves) collapsed from a binned SAH tree; AVX2 (or its "
       "AVX-512 build) when the CPU has it",
       {{"width", OptionType::choice, "auto", "children per node: 4 (SSE2), 8 (AVX2; 4 on CPUs without it), auto",
         {"auto", "4", "8"}},
        {"isa", OptionType::choice, "best",
         "instruction set of the eight-wide kernels: best (AVX-512 build where the CPU has it, else AVX2) or avx2",
         {"best", "avx2"}},
        {"bins", OptionType::integer, std::to_string(defaults.bin_count), "SAH bins per axis of the binary build (2..64)",
         {}},
        {"presplit", OptionType::real, kDefaultPresplit,
         "triangle pre-splitting (Karras & Aila 2013): extra references as a fraction of the triangle count, 0..4; 0 "
         "turns it off",
         {}},
        {"presplit_threshold", OptionType::real, kDefaultPresplitThreshold,
         "pre-split only scenes whose pre-splitting potential (box area wasted at coarse grid planes over the scene "
         "box area; reported as presplit_potential) is at least this; 0 pre-splits every triangle scene",
         {}}},
       {"bvh_wide", "bvh_wide:width=4", "bvh_wide:width=8,isa=avx2", "bvh_wide:presplit=0",
        "bvh_wide:presplit_threshold=0"},
       [](const Options& options) {
         WideBvhConfig config;
         const std::string& width = options.get("width");
         config.width = width == "auto" ? 0 : std::stoi(width);
         config.isa = options.get("isa") == "avx2" ? WideIsa::avx2 : WideIsa::best;
         if (config.width == 4 && config.isa != WideIsa::best) {
           throw Error("bvh_wide: isa=" + options.get("isa") + " applies to the eight-wide kernels, not width=4");
         }
         const long long bins = options.get_int("bins");
         if (bins < 2 || bins > 64) throw Error("bvh_wide: bins must be in 2..64, got " + std::to_string(bins));
         config.binary.bin_count = static_cast<std::uint32_t>(bins);
         const double presplit = options.get_real("presplit");
         if (!(presplit >= 0.0 && presplit <= 4.0)) {
           throw Error("bvh_wide: presplit must be in [0, 4], got " + options.get("presplit"));
         }
         config.presplit = static_cast<float>(presplit);
         const double threshold = options.get_real("presplit_threshold");
         if (!(threshold >= 0.0 && threshold <= 1e30)) {
           throw Error("bvh_wide: presplit_threshold must be a finite number >= 0, got " + options.get("presplit_threshold"));
         }
         config.presplit_threshold = static_cast<float>(threshold);
         return std::make_unique<WideBvh>(config);
       }});
}

}  // namespace rayaccel::wide
