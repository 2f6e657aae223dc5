// The raw little-endian .rays / .hits / .occ / .points / .closest / .counts exchange files, whose records are
// sequences of 4-byte words (or bytes), and the double path's .rays64 / .hits64, whose records are 8-byte words:
// copied as is on little-endian hosts and byte-swapped per word elsewhere.
#include "rayaccel/scene/ray_io.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstddef>
#include <cstring>
#include <fstream>
#include <new>
#include <limits>
#include <string>
#include <system_error>
#include <type_traits>

#include "rayaccel/core/error.h"
#include "rayaccel/core/quoted_path.h"
#include "rayaccel/core/ray_d.h"
#include "rayaccel/core/output_file.h"
#include "rayaccel/scene/file_extension.h"

namespace rayaccel {

namespace {

static_assert(sizeof(float) == 4 && std::numeric_limits<float>::is_iec559, "the files hold IEEE-754 float32");
static_assert(sizeof(Vec3) == 12, "a .points record is three float32");
static_assert(sizeof(double) == 8 && std::numeric_limits<double>::is_iec559, "the 64 files hold IEEE-754 float64");
static_assert(sizeof(RayD) == 64 && offsetof(RayD, t_min) == 24 && offsetof(RayD, t_max) == 56,
              "a .rays64 record is RayD: eight float64");

/// A .hits64 record as 8-byte words: prim_id and the zero padding after it form one little-endian word (prim_id in
/// its low half), so the record is swapped per 8-byte word like a .rays64 one.
struct HitRecordD {
  double t;
  std::uint64_t prim_id_and_padding;
  double u;
  double v;
};
static_assert(sizeof(HitRecordD) == 32, "a .hits64 record is 32 bytes");

/// Reverses the bytes of every `Word`-byte word on big-endian hosts (a no-op on little-endian ones).
template <std::size_t Word>
void to_or_from_little_endian(unsigned char* bytes, std::size_t size) {
  if constexpr (std::endian::native != std::endian::little) {
    for (std::size_t i = 0; i + Word <= size; i += Word) std::reverse(bytes + i, bytes + i + Word);
  } else {
    (void)bytes;
    (void)size;
  }
}

/// Reads the whole file as records T (each a sequence of `Word`-byte words).
template <class T, std::size_t Word = 4>
std::vector<T> read_records(const std::filesystem::path& path, const char* what) {
  static_assert(std::is_trivially_copyable_v<T>);
  // Only regular files: their size is known before reading (a device such as /dev/zero would be read forever).
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) {
    throw Error("cannot read " + std::string(what) + " file " + quoted(path) + ": it does not exist");
  }
  if (!std::filesystem::is_regular_file(status)) {
    throw Error("cannot read " + std::string(what) + " file " + quoted(path) + ": not a regular file");
  }
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw Error("cannot read " + std::string(what) + " file " + quoted(path) + ": " + ec.message());
  if (size % sizeof(T) != 0) {
    throw Error(std::string(what) + " file " + quoted(path) + " has " + std::to_string(size) +
                " bytes, not a multiple of the " + std::to_string(sizeof(T)) + "-byte record");
  }
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw Error("cannot read " + std::string(what) + " file " + quoted(path) + ": " +
                (errno != 0 ? std::strerror(errno) : "not a readable file"));
  }
  std::vector<T> records;
  try {
    records.resize(static_cast<std::size_t>(size / sizeof(T)));
  } catch (const std::bad_alloc&) {
    throw Error("cannot read " + std::string(what) + " file " + quoted(path) + ": out of memory for its " +
                std::to_string(size) + " bytes");
  }
  if (size > 0 && !in.read(reinterpret_cast<char*>(records.data()), static_cast<std::streamsize>(size))) {
    throw Error("cannot read " + std::string(what) + " file " + quoted(path) + ": it ended before its " +
                std::to_string(size) + " bytes (read error or truncated while reading)");
  }
  if constexpr (sizeof(T) % Word == 0) {
    to_or_from_little_endian<Word>(reinterpret_cast<unsigned char*>(records.data()), size);
  }
  return records;
}

template <class T, std::size_t Word = 4>
void write_records(const std::filesystem::path& path, std::span<const T> records, const char* what) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::vector<std::byte> bytes(records.size_bytes());
  if (!bytes.empty()) std::memcpy(bytes.data(), records.data(), bytes.size());
  if constexpr (sizeof(T) % Word == 0) {
    to_or_from_little_endian<Word>(reinterpret_cast<unsigned char*>(bytes.data()), bytes.size());
  }
  write_file_atomically(path, bytes, std::string(what) + " file");
}

/// Refuses a ray file whose extension names the other precision: a .rays file of an even number of records has a
/// size .rays64 accepts, and the other way round, so the size alone cannot tell them apart.
void check_ray_extension(const std::filesystem::path& path, const char* other, const char* reader) {
  if (lowercase_extension(path) == other) {
    std::string message = "ray file '";  // appended piece by piece (GCC 12 warns, wrongly, about "..." + string&&)
    message += path.string();
    message += "' is a ";
    message += other;
    message += " file by its name; ";
    message += reader;
    throw Error(message);
  }
}

}  // namespace

std::vector<Ray> read_rays(const std::filesystem::path& path) {
  check_ray_extension(path, ".rays64", "float rays are .rays (trace it with --precision double)");
  return read_records<Ray>(path, "ray");
}

void write_rays(const std::filesystem::path& path, std::span<const Ray> rays) {
  write_records<Ray>(path, rays, "ray");
}

std::vector<Hit> read_hits(const std::filesystem::path& path) { return read_records<Hit>(path, "hit"); }

void write_hits(const std::filesystem::path& path, std::span<const Hit> hits) {
  write_records<Hit>(path, hits, "hit");
}

std::vector<std::uint8_t> read_occlusion(const std::filesystem::path& path) {
  std::vector<std::uint8_t> occluded = read_records<std::uint8_t>(path, "occlusion");
  for (std::size_t i = 0; i < occluded.size(); ++i) {
    if (occluded[i] > 1) {
      throw Error("occlusion file " + quoted(path) + ": byte " + std::to_string(i) + " is " +
                  std::to_string(occluded[i]) + ", not 0 or 1");
    }
  }
  return occluded;
}

void write_occlusion(const std::filesystem::path& path, std::span<const std::uint8_t> occluded) {
  write_records<std::uint8_t>(path, occluded, "occlusion");
}

std::vector<Vec3> read_points(const std::filesystem::path& path) { return read_records<Vec3>(path, "point"); }

void write_points(const std::filesystem::path& path, std::span<const Vec3> points) {
  write_records<Vec3>(path, points, "point");
}

std::vector<ClosestPoint> read_closest_points(const std::filesystem::path& path) {
  return read_records<ClosestPoint>(path, "closest-point");
}

void write_closest_points(const std::filesystem::path& path, std::span<const ClosestPoint> points) {
  write_records<ClosestPoint>(path, points, "closest-point");
}

void write_counts(const std::filesystem::path& path, std::span<const std::uint32_t> counts) {
  write_records<std::uint32_t>(path, counts, "count");
}

std::vector<std::uint32_t> read_ids(const std::filesystem::path& path) {
  return read_records<std::uint32_t>(path, "id");
}

void write_ids(const std::filesystem::path& path, std::span<const std::uint32_t> ids) {
  write_records<std::uint32_t>(path, ids, "id");
}

std::vector<RayD> read_rays_d(const std::filesystem::path& path) {
  check_ray_extension(path, ".rays", "double rays are .rays64 (trace .rays files without --precision double)");
  return read_records<RayD, 8>(path, "ray");
}

void write_rays_d(const std::filesystem::path& path, std::span<const RayD> rays) {
  write_records<RayD, 8>(path, rays, "ray");
}

std::vector<HitD> read_hits_d(const std::filesystem::path& path) {
  const std::vector<HitRecordD> records = read_records<HitRecordD, 8>(path, "hit");
  std::vector<HitD> hits(records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    const HitRecordD& r = records[i];
    if ((r.prim_id_and_padding >> 32) != 0) {
      throw Error("hit file " + quoted(path) + ": record " + std::to_string(i) + " has padding " +
                  std::to_string(r.prim_id_and_padding >> 32) + " after its prim_id, not 0");
    }
    hits[i].t = r.t;
    hits[i].prim_id = static_cast<std::uint32_t>(r.prim_id_and_padding);
    hits[i].u = r.u;
    hits[i].v = r.v;
  }
  return hits;
}

void write_hits_d(const std::filesystem::path& path, std::span<const HitD> hits) {
  std::vector<HitRecordD> records(hits.size());
  for (std::size_t i = 0; i < hits.size(); ++i) records[i] = {hits[i].t, hits[i].prim_id, hits[i].u, hits[i].v};
  write_records<HitRecordD, 8>(path, std::span<const HitRecordD>(records), "hit");
}

}  // namespace rayaccel
