// The BVH file format's fixed parts: magic, version, header layout, scene fingerprint and checksum (FNV-1a 64).
// Layout (little endian): BvhFileHeader, nodes (node_count * node_bytes), primitive ids (slot_count * 4), part
// bounds (part_count * 24), then the checksum of every byte before it (8 bytes).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "rayaccel/scene/scene.h"

namespace rayaccel {

inline constexpr char kBvhFileMagic[8] = {'R', 'A', 'Y', 'A', 'B', 'V', 'H', '\0'};
inline constexpr std::uint32_t kBvhFileVersion = 1;

struct BvhFileHeader {
  char magic[8];                   // 8 bytes: kBvhFileMagic
  std::uint32_t version;           // 4: kBvhFileVersion
  std::uint32_t node_bytes;        // 4: sizeof(BvhNode<BV>)
  char volume[16];                 // 16: BV::kName, zero padded
  std::uint64_t scene_fingerprint; // 8: bvh_scene_fingerprint() of the scene it was built over
  std::uint32_t primitive_count;   // 4: the scene's primitive count
  std::uint32_t builder;           // 4: BvhBuilder
  std::uint32_t max_leaf_size;     // 4
  float traversal_cost;            // 4
  float intersection_cost;         // 4
  std::uint32_t depth;             // 4
  std::uint32_t node_count;        // 4
  std::uint32_t slot_count;        // 4
  std::uint32_t part_count;        // 4: slot_count for SBVH trees, else 0
  std::uint32_t flags;             // 4: bit 0: spatial splits (a primitive may be in several leaves)
};
static_assert(sizeof(BvhFileHeader) == 80, "the header is written as raw bytes");

/// Hash of the scene's kind, primitive count and every primitive's bounds: identifies the geometry a tree fits.
std::uint64_t bvh_scene_fingerprint(const Scene& scene);
/// FNV-1a 64 of the bytes.
std::uint64_t bvh_checksum(std::span<const std::byte> bytes);
/// Checks that a saved file is exactly `expected` bytes long (its counts' total, the trailing checksum included) and
/// that its last 8 bytes are the checksum of the rest; throws Error prefixed by `where` ("bvh file 'x': ") naming
/// the fault: truncated, trailing bytes, or corrupted.
void check_size_and_checksum(std::span<const std::byte> bytes, std::size_t expected, const std::string& where);
/// The registry spec that loads a BVH file whose first bytes are `head` ("bvh:bv=obb,builder=sbvh"; just "bvh" when
/// the header is cut short or of another version, which load() then reports); empty when `head` is not a BVH file.
std::string bvh_file_spec(std::span<const std::byte> head);
/// Reads a whole file; throws Error naming the file (as "<what> '<path>'") when it cannot be read.
std::vector<std::byte> read_bvh_file(const std::filesystem::path& path, const std::string& what = "bvh file");
/// Writes a whole file atomically (write_file_atomically); throws Error naming the file when it cannot be written.
void write_bvh_file(const std::filesystem::path& path, std::span<const std::byte> bytes,
                    const std::string& what = "bvh file");

}  // namespace rayaccel
