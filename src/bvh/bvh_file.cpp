// BVH file helpers: scene fingerprint, FNV-1a checksum, the spec a file loads with, whole-file reads and writes with
// errors naming the file.
#include "rayaccel/bvh/bvh_file.h"

#include <cstring>
#include <fstream>
#include <new>
#include <string>

#include "rayaccel/bvh/bvh.h"

#include "rayaccel/core/error.h"
#include "rayaccel/core/output_file.h"

namespace rayaccel {

namespace {

constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ull;
constexpr std::uint64_t kFnvPrime = 0x100000001b3ull;

void hash_bytes(std::uint64_t& h, const void* data, std::size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) h = (h ^ p[i]) * kFnvPrime;
}

}  // namespace

std::uint64_t bvh_checksum(std::span<const std::byte> bytes) {
  std::uint64_t h = kFnvOffset;
  hash_bytes(h, bytes.data(), bytes.size());
  return h;
}

void check_size_and_checksum(std::span<const std::byte> bytes, std::size_t expected, const std::string& where) {
  if (bytes.size() != expected) {
    throw Error(where + (bytes.size() < expected ? "truncated" : "has trailing bytes") + " (" +
                std::to_string(bytes.size()) + " bytes, the counts give " + std::to_string(expected) + ")");
  }
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + expected - sizeof stored, sizeof stored);
  if (stored != bvh_checksum(bytes.first(expected - sizeof stored))) {
    throw Error(where + "checksum mismatch (the file is corrupted)");
  }
}

std::uint64_t bvh_scene_fingerprint(const Scene& scene) {
  std::uint64_t h = kFnvOffset;
  const auto kind = static_cast<std::uint32_t>(scene.kind());
  const std::uint32_t count = scene.primitive_count();
  hash_bytes(h, &kind, sizeof kind);
  hash_bytes(h, &count, sizeof count);
  for (std::uint32_t id = 0; id < count; ++id) {
    const AABB& b = scene.primitive_bounds(id);
    const float v[6] = {b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z};
    hash_bytes(h, v, sizeof v);
  }
  return h;
}

std::string bvh_file_spec(std::span<const std::byte> head) {
  if (head.size() < sizeof kBvhFileMagic || std::memcmp(head.data(), kBvhFileMagic, sizeof kBvhFileMagic) != 0) {
    return {};
  }
  BvhFileHeader h{};
  if (head.size() < sizeof h) return "bvh";
  std::memcpy(&h, head.data(), sizeof h);
  if (h.version != kBvhFileVersion) return "bvh";
  h.volume[sizeof h.volume - 1] = '\0';
  std::string spec = "bvh:bv=" + std::string(h.volume);
  if (h.builder <= static_cast<std::uint32_t>(BvhBuilder::ploc)) {
    spec += std::string(",builder=") + to_string(static_cast<BvhBuilder>(h.builder));
  }
  return spec;
}

std::vector<std::byte> read_bvh_file(const std::filesystem::path& path, const std::string& what) {
  const std::string where = what + " '" + path.string() + "': ";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw Error(where + "cannot be opened for reading (not a regular file, or missing)");
  }
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw Error(where + "cannot be opened for reading");
  const auto size = static_cast<std::size_t>(in.tellg());
  std::vector<std::byte> bytes;
  try {
    bytes.resize(size);
  } catch (const std::bad_alloc&) {
    throw Error(where + "out of memory for its " + std::to_string(size) + " bytes");
  }
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size))) {
    throw Error(where + "read failed");
  }
  return bytes;
}

void write_bvh_file(const std::filesystem::path& path, std::span<const std::byte> bytes, const std::string& what) {
  write_file_atomically(path, bytes, what);
}

}  // namespace rayaccel
