// The raw little-endian exchange formats other tools read and write (.rays, .hits, .occ, .points, .closest, .counts,
// .rays64, .hits64; layouts below).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "rayaccel/core/closest_point.h"
#include "rayaccel/core/hit.h"
#include "rayaccel/core/ray.h"

namespace rayaccel {

// Layouts (raw little-endian, no header):
//   .rays  32 bytes per ray: float32 ox oy oz tmin dx dy dz tmax
//   .hits  16 bytes per ray: float32 t, uint32 prim_id, float32 u, float32 v (miss: t=+inf, prim=0xFFFFFFFF, u=v=0)
//   .occ   1 byte per ray: 1 occluded, 0 not
//   .points   12 bytes per point: float32 x y z (query points of closest-point and inside queries)
//   .closest  28 bytes per point: float32 x y z distance, uint32 prim_id, float32 u v (the ClosestPoint record;
//             nothing found: distance=+inf, prim=0xFFFFFFFF, the rest 0)
//   .counts   4 bytes per ray: uint32 (crossings per ray of an all-hits query)
//   .ids      4 bytes per ray: uint32, a companion of a .rays or .hits file with one entry per record: a primitive
//             to skip (trace --skip), a ray mask (trace --mask), a hit's geometry id; 0xFFFFFFFF means none
//   .rays64   64 bytes per ray: float64 ox oy oz tmin dx dy dz tmax (the double path's RayD)
//   .hits64   32 bytes per ray: float64 t, uint32 prim_id, uint32 0 (padding), float64 u, float64 v (the double
//             path's HitD; miss: t=+inf, prim=0xFFFFFFFF, u=v=0)

struct RayD;  // core/ray_d.h: declared here so that float code including this header sees no double types
struct HitD;

/// Throws Error naming the file when it cannot be read, is called *.rays64 (the double layout) or its size is not a
/// multiple of 32 bytes. Records are returned exactly as stored (no validation of NaN or t ranges: PreparedRay makes
/// bad rays void).
std::vector<Ray> read_rays(const std::filesystem::path& path);
/// Writes (replaces) the file; throws Error naming the file when it cannot be written.
void write_rays(const std::filesystem::path& path, std::span<const Ray> rays);
/// Throws Error naming the file when it cannot be read or its size is not a multiple of 16 bytes.
std::vector<Hit> read_hits(const std::filesystem::path& path);
/// Writes the records as given (call Hit::finish() first so misses have the documented form).
void write_hits(const std::filesystem::path& path, std::span<const Hit> hits);
/// Throws Error naming the file when it cannot be read or holds a byte other than 0 or 1.
std::vector<std::uint8_t> read_occlusion(const std::filesystem::path& path);
void write_occlusion(const std::filesystem::path& path, std::span<const std::uint8_t> occluded);
/// Throws Error naming the file when it cannot be read or its size is not a multiple of 12 bytes (values as stored).
std::vector<Vec3> read_points(const std::filesystem::path& path);
void write_points(const std::filesystem::path& path, std::span<const Vec3> points);
/// Throws Error naming the file when it cannot be read or its size is not a multiple of 28 bytes.
std::vector<ClosestPoint> read_closest_points(const std::filesystem::path& path);
void write_closest_points(const std::filesystem::path& path, std::span<const ClosestPoint> points);
void write_counts(const std::filesystem::path& path, std::span<const std::uint32_t> counts);
/// A companion .ids file; throws Error naming the file when it cannot be read or its size is not a multiple of 4.
std::vector<std::uint32_t> read_ids(const std::filesystem::path& path);
void write_ids(const std::filesystem::path& path, std::span<const std::uint32_t> ids);

/// The double path's files. Throws Error naming the file when it cannot be read, (read_rays_d) is called *.rays (the
/// float layout), or its size is not a multiple of 64 bytes; records as stored (PreparedRayD makes rays outside the
/// double domain void).
std::vector<RayD> read_rays_d(const std::filesystem::path& path);
void write_rays_d(const std::filesystem::path& path, std::span<const RayD> rays);
/// Throws Error naming the file when it cannot be read, its size is not a multiple of 32 bytes, or a record's
/// padding word is not 0 (naming the record).
std::vector<HitD> read_hits_d(const std::filesystem::path& path);
/// Writes the records as given (call HitD::finish() first), padding 0.
void write_hits_d(const std::filesystem::path& path, std::span<const HitD> hits);

}  // namespace rayaccel
