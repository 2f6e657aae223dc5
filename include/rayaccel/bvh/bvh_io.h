// Bvh<BV>::save / load: the built tree as a versioned binary file (layout in bvh_file.h). Loading checks, in order:
// size, magic, version, volume kind, node size, scene (primitive count and fingerprint), counts, checksum, and
// finally the tree's own invariants (validate()).
#pragma once

#include <cstring>
#include <string>
#include <type_traits>

#include "rayaccel/bvh/bvh.h"
#include "rayaccel/bvh/bvh_file.h"
#include "rayaccel/core/error.h"

namespace rayaccel {

template <BoundingVolume BV>
void Bvh<BV>::save(const std::filesystem::path& path) const {
  static_assert(std::is_trivially_copyable_v<Node>, "nodes are written as raw bytes");
  if (!scene_) throw Error("bvh file '" + path.string() + "': nothing was built to save");
  BvhFileHeader h{};
  std::memcpy(h.magic, kBvhFileMagic, sizeof h.magic);
  h.version = kBvhFileVersion;
  h.node_bytes = sizeof(Node);
  std::strncpy(h.volume, BV::kName, sizeof h.volume - 1);
  h.scene_fingerprint = bvh_scene_fingerprint(*scene_);
  h.primitive_count = scene_->primitive_count();
  h.builder = static_cast<std::uint32_t>(config_.builder);
  h.max_leaf_size = config_.max_leaf_size;
  h.traversal_cost = config_.costs.traversal;
  h.intersection_cost = config_.costs.intersection;
  h.depth = static_cast<std::uint32_t>(depth_);
  h.node_count = static_cast<std::uint32_t>(nodes_.size());
  h.slot_count = static_cast<std::uint32_t>(prim_ids_.size());
  h.part_count = static_cast<std::uint32_t>(part_bounds_.size());
  h.flags = spatial_splits_ ? 1u : 0u;
  std::vector<std::byte> bytes;
  auto append = [&bytes](const void* data, std::size_t size) {
    const auto* p = static_cast<const std::byte*>(data);
    bytes.insert(bytes.end(), p, p + size);
  };
  append(&h, sizeof h);
  append(nodes_.data(), nodes_.size() * sizeof(Node));
  append(prim_ids_.data(), prim_ids_.size() * sizeof(std::uint32_t));
  append(part_bounds_.data(), part_bounds_.size() * sizeof(AABB));
  const std::uint64_t sum = bvh_checksum(bytes);
  append(&sum, sizeof sum);
  write_bvh_file(path, bytes);
}

template <BoundingVolume BV>
void Bvh<BV>::load(const std::filesystem::path& path, const Scene& scene) {
  const std::string where = "bvh file '" + path.string() + "': ";
  const std::vector<std::byte> bytes = read_bvh_file(path);
  BvhFileHeader h{};
  if (bytes.size() < sizeof h) {
    throw Error(where + "truncated (" + std::to_string(bytes.size()) + " bytes, the header alone is " +
                std::to_string(sizeof h) + ")");
  }
  std::memcpy(&h, bytes.data(), sizeof h);
  if (std::memcmp(h.magic, kBvhFileMagic, sizeof h.magic) != 0) throw Error(where + "not a rayaccel BVH file");
  if (h.version != kBvhFileVersion) {
    throw Error(where + "format version " + std::to_string(h.version) + " is not supported (this build reads " +
                std::to_string(kBvhFileVersion) + ")");
  }
  h.volume[sizeof h.volume - 1] = '\0';
  if (std::string(h.volume) != BV::kName) {
    throw Error(where + "holds a '" + std::string(h.volume) + "' BVH, not '" + BV::kName + "'");
  }
  if (h.node_bytes != sizeof(Node)) {
    throw Error(where + "node size " + std::to_string(h.node_bytes) + " differs from " + std::to_string(sizeof(Node)));
  }
  if (h.primitive_count != scene.primitive_count() || h.scene_fingerprint != bvh_scene_fingerprint(scene)) {
    throw Error(where + "was built for another scene (" + std::to_string(h.primitive_count) +
                " primitives; the given scene '" + scene.name() + "' has " +
                std::to_string(scene.primitive_count()) + " and/or other geometry)");
  }
  if (h.part_count != 0 && h.part_count != h.slot_count) throw Error(where + "inconsistent part count");
  if (h.builder > static_cast<std::uint32_t>(BvhBuilder::ploc) || h.flags > 1) {
    throw Error(where + "unknown builder or flags in the header");
  }
  const std::size_t expected = sizeof h + std::size_t{h.node_count} * sizeof(Node) +
                               std::size_t{h.slot_count} * sizeof(std::uint32_t) +
                               std::size_t{h.part_count} * sizeof(AABB) + sizeof(std::uint64_t);
  check_size_and_checksum(bytes, expected, where);
  BvhOptions config = config_;
  config.builder = static_cast<BvhBuilder>(h.builder);
  config.max_leaf_size = h.max_leaf_size;
  config.costs = {h.traversal_cost, h.intersection_cost};
  bvh_option_table().check(config);
  config_ = config;
  scene_ = &scene;
  depth_ = static_cast<int>(h.depth);
  spatial_splits_ = (h.flags & 1u) != 0;
  const std::byte* p = bytes.data() + sizeof h;
  // Reads one stored array; an empty one is skipped (memcpy's pointers must not be null, even for 0 bytes).
  auto read_array = [&p](auto& array, std::size_t count) {
    array.resize(count);
    if (count == 0) return;
    std::memcpy(array.data(), p, count * sizeof(array[0]));
    p += count * sizeof(array[0]);
  };
  read_array(nodes_, h.node_count);
  read_array(prim_ids_, h.slot_count);
  read_array(part_bounds_, h.part_count);
  triangles_.clear();
  const std::vector<std::string> problems = validate();
  if (!problems.empty()) {
    nodes_.clear();
    prim_ids_.clear();
    part_bounds_.clear();
    throw Error(where + "the stored tree is invalid: " + problems.front());
  }
  copy_triangles();
  compute_statistics(0.0);
}

}  // namespace rayaccel
