// The bvh_wide file format's fixed parts: magic, version and header (the BVH family's fingerprint, checksum and file
// helpers are reused from bvh/bvh_file.h). Layout (little endian): WideBvhFileHeader, nodes (node_count *
// sizeof(Node<width>)), Triangle4 blocks (block_count * 112), then the FNV-1a checksum of every byte before it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace rayaccel::wide {

inline constexpr char kWideBvhFileMagic[8] = {'R', 'A', 'Y', 'A', 'W', 'B', 'V', 'H'};
inline constexpr std::uint32_t kWideBvhFileVersion = 2;

struct WideBvhFileHeader {
  char magic[8];                    // 8 bytes: kWideBvhFileMagic
  std::uint32_t version;            // 4: kWideBvhFileVersion
  std::uint32_t width;              // 4: children per node, 4 or 8
  std::uint64_t scene_fingerprint;  // 8: bvh_scene_fingerprint() of the scene it was built over
  std::uint32_t primitive_count;    // 4: the scene's primitive count
  std::uint32_t root;               // 4: root reference (node index, leaf reference or kEmptyChild)
  std::uint32_t node_count;         // 4
  std::uint32_t block_count;        // 4: Triangle4 blocks
  std::uint32_t depth;              // 4
  std::uint32_t flags;              // 4: bit 0: spatial splits (pre-split pieces); bit 1: triangle scene
  std::uint32_t references;         // 4: references of the binary tree (statistics)
  std::uint32_t split_triangles;    // 4: triangles pre-split (statistics)
  std::uint32_t dropped_repeats;    // 4: pieces dropped as repeats within a leaf (statistics)
  float presplit_potential;         // 4: the scene's pre-splitting potential (statistics)
};
static_assert(sizeof(WideBvhFileHeader) == 64, "the header is written as raw bytes");

/// The registry spec that loads a bvh_wide file whose first bytes are `head` ("bvh_wide:width=8"; "bvh_wide" when
/// the header is cut short or of another version, which load() then reports); empty when it is not such a file.
std::string wide_bvh_file_spec(std::span<const std::byte> head);

}  // namespace rayaccel::wide
