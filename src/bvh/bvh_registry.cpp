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
#include "rayaccel/core/error.h"

namespace rayaccel {

namespace {

struct VolumeEntry {
  const char* name;
  std::unique_ptr<Accelerator> (*make)(const BvhConfig&);
};

template <BoundingVolume BV>
std::unique_ptr<Accelerator> make_bvh(const BvhConfig& config) {
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

constexpr BvhBuilder kBuilders[] = {BvhBuilder::binned, BvhBuilder::sweep, BvhBuilder::sbvh, BvhBuilder::lbvh,
                                    BvhBuilder::ploc};

std::uint32_t get_count(const Options& options, const std::string& key) {
  const long long v = options.get_int(key);
  if (v < 0 || v > 0xFFFFFFFFll) throw Error("bvh: option '" + key + "': " + std::to_string(v) + " is out of range");
  return static_cast<std::uint32_t>(v);
}

std::unique_ptr<Accelerator> create(const Options& options) {
  BvhConfig config;
  for (BvhBuilder b : kBuilders) {
    if (options.get("builder") == to_string(b)) config.builder = b;
  }
  config.max_leaf_size = get_count(options, "leaf_size");
  config.costs = {static_cast<float>(options.get_real("traversal_cost")),
                  static_cast<float>(options.get_real("intersection_cost"))};
  config.bin_count = get_count(options, "bins");
  config.max_growth = static_cast<float>(options.get_real("max_growth"));
  config.overlap_alpha = static_cast<float>(options.get_real("overlap_alpha"));
  config.ploc_radius = get_count(options, "ploc_radius");
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
  std::vector<std::string> volumes, builders;
  for (const VolumeEntry& v : kVolumes) volumes.push_back(v.name);
  for (BvhBuilder b : kBuilders) builders.push_back(to_string(b));
  info.options = {
      {"bv", OptionType::choice, "aabb", "bounding volume of every node", volumes},
      {"builder", OptionType::choice, "binned",
       "binned SAH (Wald 2007), sweep SAH, sbvh (spatial splits, Stich 2009), lbvh (Morton, Lauterbach 2009), ploc "
       "(Meister & Bittner 2018)",
       builders},
      {"leaf_size", OptionType::integer, "4", "most primitives per leaf (1..255)", {}},
      {"traversal_cost", OptionType::real, "1", "SAH cost of visiting an interior node", {}},
      {"intersection_cost", OptionType::real, "1", "SAH cost of one primitive test", {}},
      {"bins", OptionType::integer, "16", "bins per axis for binned SAH and SBVH (2..64)", {}},
      {"max_growth", OptionType::real, "1.3", "SBVH: most references as a multiple of the primitive count", {}},
      {"overlap_alpha", OptionType::real, "1e-5", "SBVH: child overlap (fraction of root area) that triggers spatial splits", {}},
      {"ploc_radius", OptionType::integer, "16", "PLOC: neighbours searched on each side in Morton order", {}},
  };
  for (const std::string& v : volumes) {
    for (const std::string& b : builders) info.variants.push_back("bvh:bv=" + v + ",builder=" + b);
  }
  info.create = create;
  registry.push_back(std::move(info));
}

}  // namespace rayaccel
