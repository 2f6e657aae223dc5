// The "bvh" registry entry: option parsing and the table of bounding volumes (one line per volume).
#include "rayaccel/bvh/bvh_registry.h"

#include <memory>
#include <string>

#include "rayaccel/bv/aabb_volume.h"
#include "rayaccel/bv/capsule_volume.h"
#include "rayaccel/bv/hull_volume.h"
#include "rayaccel/bv/kdop_volume.h"
#include "rayaccel/bv/obb_volume.h"
#include "rayaccel/bv/sphere_volume.h"
#include "rayaccel/bvh/bvh.h"
#include "rayaccel/bvh/bvh_file.h"
#include "rayaccel/core/error.h"

namespace rayaccel {

namespace {

struct VolumeEntry {
  const char* name;
  std::unique_ptr<Accelerator> (*make)(const BvhOptions&);
};

template <BoundingVolume BV>
std::unique_ptr<Accelerator> make_bvh(const BvhOptions& config) {
  return std::make_unique<Bvh<BV>>(config);
}

const VolumeEntry kVolumes[] = {
    {AabbVolume::kName, &make_bvh<AabbVolume>},
    {SphereVolume::kName, &make_bvh<SphereVolume>},
    {ObbVolume::kName, &make_bvh<ObbVolume>},
    {Kdop14Volume::kName, &make_bvh<Kdop14Volume>},
    {Kdop18Volume::kName, &make_bvh<Kdop18Volume>},
    {Kdop26Volume::kName, &make_bvh<Kdop26Volume>},
    {HullVolume::kName, &make_bvh<HullVolume>},
    {CapsuleVolume::kName, &make_bvh<CapsuleVolume>},
};

std::unique_ptr<Accelerator> create(const OptionValues& options) {
  const BvhOptions config = bvh_option_table().parse(options);
  for (const VolumeEntry& v : kVolumes) {
    if (options.get("bv") == v.name) return v.make(config);
  }
  throw Error("bvh: unknown bounding volume '" + options.get("bv") + "'");
}

}  // namespace

void register_bvh(std::vector<AcceleratorInfo>& registry) {
  AcceleratorInfo info;
  info.name = "bvh";
  info.description = "bounding volume hierarchy: AABB/sphere/OBB/k-DOP/hull/capsule volumes; binned SAH, sweep SAH, SBVH, LBVH, PLOC";
  std::vector<std::string> volumes;
  for (const VolumeEntry& v : kVolumes) volumes.push_back(v.name);
  info.options = {{"bv", OptionType::choice, "aabb", "bounding volume of every node", volumes, {}}};
  for (const OptionSpec& spec : bvh_option_table().specs()) info.options.push_back(spec);
  for (const std::string& v : volumes) {
    for (const OptionSpec& builder : info.options) {
      if (builder.key != "builder") continue;
      for (const std::string& b : builder.choices) info.variants.push_back("bvh:bv=" + v + ",builder=" + b);
    }
  }
  info.create = create;
  info.saved_spec = bvh_file_spec;
  registry.push_back(std::move(info));
}

}  // namespace rayaccel
