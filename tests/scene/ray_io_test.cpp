// Unit tests of the raw .rays / .hits / .occ files and the double path's .rays64 / .hits64: exact byte layout, round
// trips, and errors naming the file.
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
#include "rayaccel/core/ray_d.h"
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

/// The little-endian bytes of an IEEE float64 or uint32 value, as the files hold them.
template <class T>
std::string little_endian(T value) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof(T));
  std::string out;
  for (std::size_t b = 0; b < sizeof(T); ++b) out += static_cast<char>((bits >> (8 * b)) & 0xFFu);
  return out;
}

TEST(RayIo, Rays64AndHits64HaveTheDocumentedLittleEndianLayout) {
  TempDir dir;
  const std::vector<RayD> rays = {{{1e7 + 0.1, -2.0, 3.5}, 0.25, {0.0, -0.0, 1.0 / 3.0}, 100.0}};
  write_rays_d(dir.path() / "one.rays64", rays);
  std::string expected;
  for (double x : {1e7 + 0.1, -2.0, 3.5, 0.25, 0.0, -0.0, 1.0 / 3.0, 100.0}) expected += little_endian(x);
  EXPECT_EQ(file_bytes(dir.path() / "one.rays64"), expected);

  std::vector<HitD> hits(2);
  hits[0].t = 1e-3 / 7.0;
  hits[0].prim_id = 0x01020304u;
  hits[0].u = 0.25;
  hits[0].v = 1.0 / 3.0;
  hits[1].finish();
  write_hits_d(dir.path() / "two.hits64", hits);
  const double inf = std::numeric_limits<double>::infinity();
  expected = little_endian(1e-3 / 7.0) + little_endian(0x01020304u) + little_endian(0u) + little_endian(0.25) +
             little_endian(1.0 / 3.0);
  expected += little_endian(inf) + little_endian(0xFFFFFFFFu) + little_endian(0u) + little_endian(0.0) +
              little_endian(0.0);
  EXPECT_EQ(file_bytes(dir.path() / "two.hits64"), expected);
}

TEST(RayIo, Rays64AndHits64RoundTripsKeepEveryBit) {
  TempDir dir;
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<RayD> rays = {{{0, 0, 0}, 0.0, {1, 0, 0}, inf},
                                  {{1e300, -1e-300, 7.0 + 0x1p-50}, -0.0, {-0.0, 0.0, -1.0}, 0.0},
                                  {{nan, 1, 2}, 1.0, {1, 2, 3}, 2.0}};
  write_rays_d(dir.path() / "r.rays64", rays);
  const std::vector<RayD> back = read_rays_d(dir.path() / "r.rays64");
  ASSERT_EQ(back.size(), rays.size());
  EXPECT_EQ(std::memcmp(back.data(), rays.data(), rays.size() * sizeof(RayD)), 0);

  std::vector<HitD> hits(2);
  hits[0].t = 1e7 + 0x1p-29;
  hits[0].prim_id = 42;
  hits[0].u = 0x1p-60;
  hits[0].v = 0.5 - 0x1p-54;
  hits[1].finish();
  write_hits_d(dir.path() / "h.hits64", hits);
  EXPECT_EQ(std::filesystem::file_size(dir.path() / "h.hits64"), 64u);
  const std::vector<HitD> hits_back = read_hits_d(dir.path() / "h.hits64");
  ASSERT_EQ(hits_back.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(hits_back[i].t, hits[i].t);
    EXPECT_EQ(hits_back[i].prim_id, hits[i].prim_id);
    EXPECT_EQ(hits_back[i].u, hits[i].u);
    EXPECT_EQ(hits_back[i].v, hits[i].v);
  }
  EXPECT_TRUE(read_rays_d(dir.write("e.rays64", "")).empty());
  EXPECT_TRUE(read_hits_d(dir.write("e.hits64", "")).empty());
}

TEST(RayIo, Rays64AndHits64BadSizesAndPaddingNameTheFile) {
  TempDir dir;
  // A .rays file of one ray is not a .rays64 file: 32 bytes is not a multiple of 64.
  const auto rays32 = dir.write("float.rays64", std::string(32, '\0'));
  expect_error_naming([&] { read_rays_d(rays32); }, "float.rays64", "has 32 bytes, not a multiple of the 64-byte");
  const auto hits48 = dir.write("bad48.hits64", std::string(48, '\0'));
  expect_error_naming([&] { read_hits_d(hits48); }, "bad48.hits64", "has 48 bytes, not a multiple of the 32-byte");
  std::string record(64, '\0');
  record[32 + 12] = 1;  // the second record's padding word
  const auto padded = dir.write("padded.hits64", record);
  expect_error_naming([&] { read_hits_d(padded); }, "padded.hits64", "record 1 has padding 1");
  expect_error_naming([&] { read_rays_d(dir.path() / "missing.rays64"); }, "missing.rays64", "cannot read");
  const std::vector<HitD> none;
  expect_error_naming([&] { write_hits_d(dir.path() / "no_dir" / "x.hits64", none); }, "x.hits64", "cannot write");
}

}  // namespace
}  // namespace rayaccel
