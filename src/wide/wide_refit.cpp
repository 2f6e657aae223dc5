// Wide BVH refit after vertex motion: Triangle4 copies refreshed, child boxes recomputed bottom-up in one backward
// pass over the nodes (the refitting of Wald, Boulos, Shirley 2007, "Ray tracing deformable scenes using dynamic
// bounding volume hierarchies", applied to the collapsed wide nodes), and update(), which refits or rebuilds.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <string>

#include "rayaccel/core/error.h"
#include "rayaccel/wide/wide_bvh.h"

namespace rayaccel::wide {

std::vector<std::uint32_t> WideBvh::leaf_prim_ids() const {
  std::vector<std::uint32_t> ids;
  ids.reserve(blocks_.size() * 4);
  simd::for_each_block_id(blocks_.data(), static_cast<std::uint32_t>(blocks_.size()),
                          [&](const simd::Triangle4& block, int lane) { ids.push_back(block.prim_id[lane]); });
  return ids;
}

AABB WideBvh::leaf_box(std::uint32_t ref) const {
  AABB box;
  // Whole primitives, also for pre-split pieces: the leaf's box then holds every triangle it tests.
  for_each_leaf_prim(ref, [&](std::uint32_t id) { box.extend(scene_->primitive_bounds(id)); });
  return box;
}

template <int W>
void WideBvh::refit_nodes(NodeArray<W>& nodes) {
  // Leaf children first, in parallel (the scene's bounds are read at random); then inner children, whose boxes are
  // the union of their own node's children: a backward pass, as every node's children come after it.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nodes.size(), 256), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      Node<W>& node = nodes[i];
      for (int lane = 0; lane < W; ++lane) {
        if (node.child[lane] != kEmptyChild && (node.child[lane] & kLeafBit)) {
          set_child_bounds(node, lane, leaf_box(node.child[lane]));
        }
      }
    }
  });
  for (std::size_t i = nodes.size(); i-- > 0;) {
    Node<W>& node = nodes[i];
    for (int lane = 0; lane < W; ++lane) {
      const std::uint32_t ref = node.child[lane];
      if (ref == kEmptyChild || (ref & kLeafBit)) continue;
      AABB box;
      for (int c = 0; c < W; ++c) {
        if (nodes[ref].child[c] != kEmptyChild) box.extend(child_bounds(nodes[ref], c));
      }
      set_child_bounds(node, lane, box);
    }
  }
  // The any-hit order follows the boxes (any order gives the same answers; this one keeps near-first).
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nodes.size(), 256), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) set_child_order(nodes[i]);
  });
}

void WideBvh::refit() {
  if (!scene_) throw Error("bvh_wide refit: nothing was built");
  // The range check reads the blocks in place (no gathered copy of the ids: update() has just made one).
  std::uint32_t max_id = 0;
  simd::for_each_block_id(blocks_.data(), static_cast<std::uint32_t>(blocks_.size()),
                          [&](const simd::Triangle4& block, int lane) {
                            max_id = std::max(max_id, block.prim_id[lane]);
                          });
  if (!blocks_.empty() && max_id >= scene_->primitive_count()) {
    throw Error("bvh_wide refit: the tree refers to primitive " + std::to_string(max_id) + ", but the scene has " +
                std::to_string(scene_->primitive_count()) + "; rebuild instead");
  }
  if (triangles_) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks_.size(), 1024), [&](const auto& range) {
      for (std::size_t b = range.begin(); b < range.end(); ++b) {
        for (int lane = 0; lane < 4; ++lane) {
          if (blocks_[b].prim_id[lane] != kInvalidPrimId) {
            simd::set_block_lane(blocks_[b], lane, *scene_, blocks_[b].prim_id[lane]);
          }
        }
      }
    });
  }
  if (width_ == 8) {
    refit_nodes(nodes8_);
  } else {
    refit_nodes(nodes4_);
  }
}

UpdateKind WideBvh::update(const Scene& scene) {
  if (scene_ == &scene && detail::refit_covers_scene(scene, leaf_prim_ids())) {
    refit();
    return UpdateKind::refitted;
  }
  build(scene);
  return UpdateKind::rebuilt;
}

}  // namespace rayaccel::wide
