// Unit tests of the raw .rays / .hits / .occ files: exact byte layout, round trips, and errors naming the file.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "rayaccel/core/error.h"
#include "rayaccel/scene/ray_io.h"
#include "temp_dir.h"

namespace rayaccel {
namespace {

using testing::TempDir;

std::string file_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void expect_error_naming(const std::function<void()>& f, const std::string& name, const std::string& fault) {
  try {
    f();
    ADD_FAILURE() << "no error for " << name;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(fault), std::string::npos) << e.what();
  }
}

TEST(RayIo, RaysHaveTheDocumentedLittleEndianLayout) {
  TempDir dir;
  const std::vector<Ray> rays = {{{1.0f, -2.0f, 3.5f}, 0.25f, {0.0f, -0.0f, 1.0f}, 100.0f}};
  const auto file = dir.path() / "one.rays";
  write_rays(file, rays);
  const std::string bytes = file_bytes(file);
  ASSERT_EQ(bytes.size(), 32u);
  const float expected[8] = {1.0f, -2.0f, 3.5f, 0.25f, 0.0f, -0.0f, 1.0f, 100.0f};
  for (int i = 0; i < 8; ++i) {
    std::uint32_t bits;
    std::memcpy(&bits, &expected[i], 4);
    for (int b = 0; b < 4; ++b) {
      EXPECT_EQ(static_cast<unsigned char>(bytes[4 * i + b]), (bits >> (8 * b)) & 0xFFu) << "word " << i;
    }
  }
}

TEST(RayIo, RoundTripsKeepEveryBit) {
  TempDir dir;
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Ray> rays = {{{0, 0, 0}, 0.0f, {1, 0, 0}, inf},
                           {{1e15f, -1e-30f, 7.0f}, -0.0f, {-0.0f, 0.0f, -1.0f}, 0.0f},
                           {{nan, 1, 2}, 1.0f, {1, 2, 3}, 2.0f}};
  write_rays(dir.path() / "r.rays", rays);
  const std::vector<Ray> back = read_rays(dir.path() / "r.rays");
  ASSERT_EQ(back.size(), rays.size());
  EXPECT_EQ(std::memcmp(back.data(), rays.data(), rays.size() * sizeof(Ray)), 0);

  std::vector<Hit> hits(2);
  hits[0] = {1.5f, 42u, 0.25f, 0.5f};
  hits[1].finish();
  write_hits(dir.path() / "h.hits", hits);
  EXPECT_EQ(std::filesystem::file_size(dir.path() / "h.hits"), 32u);
  const std::vector<Hit> hits_back = read_hits(dir.path() / "h.hits");
  ASSERT_EQ(hits_back.size(), 2u);
  EXPECT_EQ(std::memcmp(hits_back.data(), hits.data(), 2 * sizeof(Hit)), 0);
  EXPECT_EQ(hits_back[1].prim_id, kInvalidPrimId);
  EXPECT_EQ(hits_back[1].t, inf);

  const std::vector<std::uint8_t> occ = {1, 0, 0, 1, 1};
  write_occlusion(dir.path() / "o.occ", occ);
  EXPECT_EQ(file_bytes(dir.path() / "o.occ"), std::string("\x01\x00\x00\x01\x01", 5));
  EXPECT_EQ(read_occlusion(dir.path() / "o.occ"), occ);
}

TEST(RayIo, EmptyFilesHoldNoRecords) {
  TempDir dir;
  EXPECT_TRUE(read_rays(dir.write("e.rays", "")).empty());
  EXPECT_TRUE(read_hits(dir.write("e.hits", "")).empty());
  EXPECT_TRUE(read_occlusion(dir.write("e.occ", "")).empty());
}

TEST(RayIo, BadSizesAndMissingFilesNameTheFile) {
  TempDir dir;
  const auto rays33 = dir.write("bad33.rays", std::string(33, '\0'));
  expect_error_naming([&] { read_rays(rays33); }, "bad33.rays", "multiple of the 32-byte");
  const auto hits20 = dir.write("bad20.hits", std::string(20, '\0'));
  expect_error_naming([&] { read_hits(hits20); }, "bad20.hits", "multiple of the 16-byte");
  const auto occ2 = dir.write("bad.occ", std::string("\x01\x02", 2));
  expect_error_naming([&] { read_occlusion(occ2); }, "bad.occ", "not 0 or 1");
  expect_error_naming([&] { read_rays(dir.path() / "missing.rays"); }, "missing.rays", "cannot read");
  expect_error_naming([&] { read_hits(dir.path()); }, dir.path().string(), "cannot read");
  const std::vector<Ray> none;
  expect_error_naming([&] { write_rays(dir.path() / "no_dir" / "x.rays", none); }, "x.rays", "cannot write");
}

}  // namespace
}  // namespace rayaccel
