// The .ihits writer (see instance_hits_file.h).
#include "rayaccel/instance/instance_hits_file.h"

#include <vector>

#include "rayaccel/core/output_file.h"

namespace rayaccel {

void write_instance_hits(const std::filesystem::path& path, std::span<const InstanceHit> hits) {
  std::vector<InstanceHitRecord> records;
  records.reserve(hits.size());
  for (const InstanceHit& hit : hits) records.push_back(to_record(hit));
  write_file_atomically(path, std::as_bytes(std::span<const InstanceHitRecord>(records)), "instance hit file");
}

}  // namespace rayaccel
