// The .ihits file: one 24-byte little-endian record per ray of an instanced trace (t, prim_id, u, v, geom_id,
// instance_id; a miss: t = +inf, ids 0xFFFFFFFF), the layout of the CLI's files and Python's IHIT_DTYPE.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

#include "rayaccel/instance/instanced_accelerator.h"

namespace rayaccel {

struct InstanceHitRecord {
  float t;
  std::uint32_t prim_id;
  float u;
  float v;
  std::uint32_t geom_id;
  std::uint32_t instance_id;
};
static_assert(sizeof(InstanceHitRecord) == 24, ".ihits records are 24 bytes");

inline InstanceHitRecord to_record(const InstanceHit& hit) {
  return {hit.t, hit.prim_id, hit.u, hit.v, hit.geom_id, hit.instance_id};
}

/// Writes one record per hit (whole or not at all, see core/output_file.h); Error naming the file on failure.
void write_instance_hits(const std::filesystem::path& path, std::span<const InstanceHit> hits);

}  // namespace rayaccel
