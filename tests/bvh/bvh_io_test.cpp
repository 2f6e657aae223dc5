// BVH save/load: round trip (same nodes, same hits, valid), and clear errors for missing, truncated, foreign,
// wrong-version, corrupted and wrong-scene files.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "../file_bytes.h"
#include "bvh_test_scenes.h"
#include "rayaccel/bv/capsule_volume.h"
#include "rayaccel/bv/hull_volume.h"
#include "rayaccel/bvh/bvh.h"

namespace rayaccel {
namespace {

namespace fs = std::filesystem;

using testing::expect_error;
using testing::read_all;
using testing::write_all;

class BvhSaveLoad : public ::testing::TestWithParam<BvhBuilder> {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("rayaccel_bvh_io_" + std::to_string(::getpid()) + "_" +
                                        to_string(GetParam()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_P(BvhSaveLoad, RoundTripGivesSameTreeAndHits) {
  const Scene scene = bvh_test::random_soup(2000, 21);
  BvhOptions config;
  config.builder = GetParam();
  Bvh<AabbVolume> built(config);
  built.build(scene);
  const fs::path file = dir_ / "tree.bvh";
  built.save(file);
  Bvh<AabbVolume> loaded;
  loaded.load(file, scene);
  EXPECT_TRUE(loaded.validate().empty());
  ASSERT_EQ(loaded.nodes().size(), built.nodes().size());
  EXPECT_EQ(std::memcmp(loaded.nodes().data(), built.nodes().data(), built.nodes().size() * sizeof(built.nodes()[0])),
            0);
  EXPECT_EQ(loaded.depth(), built.depth());
  EXPECT_EQ(loaded.options().max_leaf_size, built.options().max_leaf_size);
  for (const Ray& r : bvh_test::random_rays(scene.bounds(), 500, 3)) {
    const Hit a = built.intersect(r), b = loaded.intersect(r);
    EXPECT_EQ(a.prim_id, b.prim_id);
    EXPECT_EQ(a.t, b.t);
  }
}

TEST_P(BvhSaveLoad, BadFilesGiveErrorsNamingFileAndFault) {
  const Scene scene = bvh_test::random_soup(300, 22);
  BvhOptions config;
  config.builder = GetParam();
  Bvh<AabbVolume> built(config);
  built.build(scene);
  const fs::path good = dir_ / "good.bvh";
  built.save(good);
  const std::vector<char> bytes = read_all(good);
  Bvh<AabbVolume> target;

  const fs::path missing = dir_ / "missing.bvh";
  expect_error([&] { target.load(missing, scene); }, missing, "cannot be opened");

  const fs::path truncated = dir_ / "truncated.bvh";
  write_all(truncated, std::vector<char>(bytes.begin(), bytes.begin() + static_cast<long>(bytes.size() / 2)));
  expect_error([&] { target.load(truncated, scene); }, truncated, "truncated");
  write_all(truncated, std::vector<char>(bytes.begin(), bytes.begin() + 10));
  expect_error([&] { target.load(truncated, scene); }, truncated, "truncated");

  const fs::path foreign = dir_ / "foreign.bvh";
  std::vector<char> text(200, 'x');
  write_all(foreign, text);
  expect_error([&] { target.load(foreign, scene); }, foreign, "not a rayaccel BVH file");

  const fs::path version = dir_ / "version.bvh";
  std::vector<char> patched = bytes;
  const std::uint32_t future = kBvhFileVersion + 1;
  std::memcpy(patched.data() + offsetof(BvhFileHeader, version), &future, sizeof future);
  write_all(version, patched);
  expect_error([&] { target.load(version, scene); }, version, "version 2 is not supported");

  const fs::path volume = dir_ / "volume.bvh";
  patched = bytes;
  std::memcpy(patched.data() + offsetof(BvhFileHeader, volume), "kdop26", 7);
  write_all(volume, patched);
  expect_error([&] { target.load(volume, scene); }, volume, "'kdop26' BVH, not 'aabb'");

  const fs::path corrupted = dir_ / "corrupted.bvh";
  patched = bytes;
  patched[sizeof(BvhFileHeader) + 5] ^= 0x40;
  write_all(corrupted, patched);
  expect_error([&] { target.load(corrupted, scene); }, corrupted, "checksum mismatch");

  const Scene other = bvh_test::random_soup(300, 23);
  expect_error([&] { target.load(good, other); }, good, "another scene");
  const Scene smaller = bvh_test::random_soup(200, 22);
  expect_error([&] { target.load(good, smaller); }, good, "another scene");

  target.load(good, scene);  // a failed load leaves the object usable
  EXPECT_TRUE(target.validate().empty());
}

// The volumes whose nodes are not boxes: the file carries their bytes unchanged, and a loaded tree answers alike.
template <class BV>
void expect_round_trip(const fs::path& file) {
  const Scene scene = bvh_test::random_soup(1000, 22);
  Bvh<BV> built;
  built.build(scene);
  built.save(file);
  Bvh<BV> loaded;
  loaded.load(file, scene);
  EXPECT_TRUE(loaded.validate().empty()) << BV::kName;
  ASSERT_EQ(loaded.nodes().size(), built.nodes().size()) << BV::kName;
  EXPECT_EQ(std::memcmp(loaded.nodes().data(), built.nodes().data(), built.nodes().size() * sizeof(built.nodes()[0])),
            0)
      << BV::kName;
  for (const Ray& r : bvh_test::random_rays(scene.bounds(), 300, 4)) {
    const Hit a = built.intersect(r), b = loaded.intersect(r);
    EXPECT_EQ(a.prim_id, b.prim_id) << BV::kName;
    EXPECT_EQ(a.t, b.t) << BV::kName;
  }
  Bvh<AabbVolume> other;
  expect_error([&] { other.load(file, scene); }, file, std::string("'") + BV::kName + "' BVH, not 'aabb'");
}

TEST(BvhSaveLoadVolumes, HullAndCapsuleTreesRoundTrip) {
  const fs::path dir = fs::temp_directory_path() / ("rayaccel_bvh_io_volumes_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  expect_round_trip<HullVolume>(dir / "hull.bvh");
  expect_round_trip<CapsuleVolume>(dir / "capsule.bvh");
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(AllBuilders, BvhSaveLoad,
                         ::testing::Values(BvhBuilder::binned, BvhBuilder::sbvh, BvhBuilder::ploc),
                         [](const ::testing::TestParamInfo<BvhBuilder>& param) { return to_string(param.param); });

}  // namespace
}  // namespace rayaccel
