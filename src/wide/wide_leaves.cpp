// Wide BVH leaves: the primitives of each binary leaf (pieces of a pre-split primitive kept once) packed into runs of
// Triangle4 blocks, reserved during the collapse and filled afterwards in parallel.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel::wide {

std::size_t WideBvh::leaf_ids(const BuildTree& tree, std::uint32_t binary_node, std::uint32_t* ids,
                              LeafIdCounts& dropped) const {
  const BuildNode& n = tree.nodes[binary_node];
  std::size_t count = 0;
  dropped = {};
  for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
    const std::uint32_t id = tree.refs[i].prim_id;
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
                          simd::Triangle4& block = blocks_[leaf.first_block + i / 4];
                          const int lane = static_cast<int>(i % 4);
                          if (i < count && triangles_) {
                            simd::set_block_lane(block, lane, *scene_, ids[i]);
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

}  // namespace rayaccel::wide
