// bvh_wide save / load (layout in wide/wide_bvh_file.h). Loading checks, in order: size, magic, version, width (this
// CPU must run it), scene (primitive count, fingerprint, kind), counts, checksum, and finally validate(), which also
// compares every Triangle4 copy with the scene's triangles.
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "rayaccel/bvh/bvh_file.h"
#include "rayaccel/core/error.h"
#include "rayaccel/wide/wide_bvh.h"
#include "rayaccel/wide/wide_bvh_file.h"

namespace rayaccel::wide {

namespace {

constexpr std::uint32_t kSpatialSplitsFlag = 1u;
constexpr std::uint32_t kTrianglesFlag = 2u;
constexpr const char* kWhat = "bvh_wide file";

std::size_t node_bytes(std::uint32_t width) { return width == 8 ? sizeof(Node<8>) : sizeof(Node<4>); }

}  // namespace

std::string wide_bvh_file_spec(std::span<const std::byte> head) {
  if (head.size() < sizeof kWideBvhFileMagic ||
      std::memcmp(head.data(), kWideBvhFileMagic, sizeof kWideBvhFileMagic) != 0) {
    return {};
  }
  WideBvhFileHeader h{};
  if (head.size() < sizeof h) return "bvh_wide";
  std::memcpy(&h, head.data(), sizeof h);
  if (h.version != kWideBvhFileVersion || (h.width != 4 && h.width != 8)) return "bvh_wide";
  return "bvh_wide:width=" + std::to_string(h.width);
}

void WideBvh::save(const std::filesystem::path& path) const {
  static_assert(std::is_trivially_copyable_v<Node<8>> && std::is_trivially_copyable_v<simd::Triangle4>,
                "nodes and blocks are written as raw bytes");
  if (!scene_) throw Error(std::string(kWhat) + " '" + path.string() + "': nothing was built to save");
  WideBvhFileHeader h{};
  std::memcpy(h.magic, kWideBvhFileMagic, sizeof h.magic);
  h.version = kWideBvhFileVersion;
  h.width = static_cast<std::uint32_t>(width_);
  h.scene_fingerprint = bvh_scene_fingerprint(*scene_);
  h.primitive_count = scene_->primitive_count();
  h.root = root_;
  h.node_count = static_cast<std::uint32_t>(width_ == 8 ? nodes8_.size() : nodes4_.size());
  h.block_count = static_cast<std::uint32_t>(blocks_.size());
  h.depth = static_cast<std::uint32_t>(depth_);
  h.flags = (spatial_splits_ ? kSpatialSplitsFlag : 0u) | (triangles_ ? kTrianglesFlag : 0u);
  h.references = references_;
  h.split_triangles = split_triangles_;
  h.dropped_repeats = dropped_repeats_;
  h.presplit_potential = static_cast<float>(presplit_potential_);
  std::vector<std::byte> bytes;
  const auto append = [&bytes](const void* data, std::size_t size) {
    const auto* p = static_cast<const std::byte*>(data);
    bytes.insert(bytes.end(), p, p + size);
  };
  append(&h, sizeof h);
  if (width_ == 8) {
    append(nodes8_.data(), nodes8_.size() * sizeof(Node<8>));
  } else {
    append(nodes4_.data(), nodes4_.size() * sizeof(Node<4>));
  }
  append(blocks_.data(), blocks_.size() * sizeof(simd::Triangle4));
  const std::uint64_t sum = bvh_checksum(bytes);
  append(&sum, sizeof sum);
  write_bvh_file(path, bytes, kWhat);
}

void WideBvh::load(const std::filesystem::path& path, const Scene& scene) {
  const std::string where = std::string(kWhat) + " '" + path.string() + "': ";
  const std::vector<std::byte> bytes = read_bvh_file(path, kWhat);
  WideBvhFileHeader h{};
  if (bytes.size() < sizeof h) {
    throw Error(where + "truncated (" + std::to_string(bytes.size()) + " bytes, the header alone is " +
                std::to_string(sizeof h) + ")");
  }
  std::memcpy(&h, bytes.data(), sizeof h);
  if (std::memcmp(h.magic, kWideBvhFileMagic, sizeof h.magic) != 0) {
    throw Error(where + "not a rayaccel bvh_wide file");
  }
  if (h.version != kWideBvhFileVersion) {
    throw Error(where + "format version " + std::to_string(h.version) + " is not supported (this build reads " +
                std::to_string(kWideBvhFileVersion) + ")");
  }
  if (h.width != 4 && h.width != 8) throw Error(where + "unknown node width " + std::to_string(h.width));
  if (h.width == 8 && !runs_eight_wide()) {
    throw Error(where + "holds eight-wide nodes, which need AVX2; this CPU (or build) runs only four-wide ones "
                "(rebuild here, or save with width=4)");
  }
  const bool triangles = scene.kind() == PrimitiveKind::triangles;
  if (h.primitive_count != scene.primitive_count() || h.scene_fingerprint != bvh_scene_fingerprint(scene) ||
      ((h.flags & kTrianglesFlag) != 0) != triangles) {
    throw Error(where + "was built for another scene (" + std::to_string(h.primitive_count) +
                " primitives; the given scene '" + scene.name() + "' has " +
                std::to_string(scene.primitive_count()) + " and/or other geometry)");
  }
  if (h.flags > (kSpatialSplitsFlag | kTrianglesFlag)) throw Error(where + "unknown flags in the header");
  const std::size_t expected = sizeof h + std::size_t{h.node_count} * node_bytes(h.width) +
                               std::size_t{h.block_count} * sizeof(simd::Triangle4) + sizeof(std::uint64_t);
  check_size_and_checksum(bytes, expected, where);
  // The file is sound: take it over, then check the tree itself (a failure leaves this object empty but usable).
  scene_ = &scene;
  select_kernels(static_cast<int>(h.width));  // the width the file holds: this CPU runs it (checked above)
  triangles_ = triangles;
  spatial_splits_ = (h.flags & kSpatialSplitsFlag) != 0;
  root_ = h.root;
  depth_ = static_cast<int>(h.depth);
  references_ = h.references;
  split_triangles_ = h.split_triangles;
  dropped_repeats_ = h.dropped_repeats;
  presplit_potential_ = h.presplit_potential;
  const std::byte* p = bytes.data() + sizeof h;
  const auto read_array = [&p](auto& array, std::size_t count) {
    array.clear();
    array.resize(count);
    if (count == 0) return;
    std::memcpy(static_cast<void*>(array.data()), p, count * sizeof(array[0]));
    p += count * sizeof(array[0]);
  };
  nodes4_.clear();
  nodes8_.clear();
  if (width_ == 8) {
    read_array(nodes8_, h.node_count);
  } else {
    read_array(nodes4_, h.node_count);
  }
  read_array(blocks_, h.block_count);
  std::vector<std::string> problems;
  if (depth_ > kBvhMaxDepth) problems.push_back("depth " + std::to_string(depth_) + " exceeds the stack bound");
  if (root_ != kEmptyChild && !(root_ & kLeafBit) && root_ >= h.node_count) problems.push_back("root out of range");
  if (problems.empty()) problems = validate();
  if (!problems.empty()) {
    nodes4_.clear();
    nodes8_.clear();
    blocks_.clear();
    root_ = kEmptyChild;
    throw Error(where + "the stored tree is invalid: " + problems.front());
  }
}

}  // namespace rayaccel::wide
