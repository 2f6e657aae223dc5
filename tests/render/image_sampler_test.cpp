// The corner sampler traces each point of the fine grid once: uniform n x n costs (n w + 1) (n h + 1) rays (16 per
// pixel plus a border at n = 4, not the 22 it cost while points on an edge between two pixels were traced by both),
// and adaptive sampling never traces a point twice either, across rows of different threads and chunks.
#include <gtest/gtest.h>

#include <cstdint>
#include <map>
#include <mutex>

#include "rayaccel/render/image_sampler.h"

namespace rayaccel {
namespace {

struct Counter {
  std::mutex lock;
  std::map<std::uint64_t, int> calls;
  std::uint64_t total = 0;
  void add(std::uint64_t key) {
    const std::lock_guard<std::mutex> guard(lock);
    ++calls[key];
    ++total;
  }
};

TEST(ImageSampler, UniformTracesEveryPointOnce) {
  for (const int n : {1, 2, 4}) {
    Counter counter;
    const int w = 9, h = 37;  // more rows than one chunk of the sampler (16)
    const SampledImage image = sample_image(w, h, parse_anti_aliasing("uniform:n=" + std::to_string(n)),
                                            [&](float x, float y, std::uint64_t key) {
                                              counter.add(key);
                                              return Vec3{x, y, 1.0f};
                                            });
    const std::uint64_t expected = std::uint64_t(n * w + 1) * std::uint64_t(n * h + 1);
    EXPECT_EQ(counter.total, expected) << "n " << n;
    EXPECT_EQ(counter.calls.size(), expected) << "n " << n;
    EXPECT_EQ(image.sample_count, expected) << "n " << n;
    // A linear image: each pixel's value is its centre, whichever pixel traced its shared points.
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const Vec3 v = image.pixels[std::size_t(y) * w + x];
        EXPECT_NEAR(v.x, x + 0.5f, 1e-4f);
        EXPECT_NEAR(v.y, y + 0.5f, 1e-4f);
      }
    }
  }
}

TEST(ImageSampler, AdaptiveTracesNoPointTwice) {
  Counter counter;
  // A diagonal edge crossing many pixels: their shared edges are subdivided from both sides.
  const SampledImage image = sample_image(23, 35, parse_anti_aliasing("adaptive:threshold=0.1,max_level=3"),
                                          [&](float x, float y, std::uint64_t key) {
                                            counter.add(key);
                                            return x + 0.7f * y < 20.3f ? Vec3{1.0f} : Vec3{0.0f};
                                          });
  for (const auto& [key, count] : counter.calls) EXPECT_EQ(count, 1) << "key " << key;
  EXPECT_EQ(image.sample_count, counter.total);
  EXPECT_GT(counter.total, 24u * 36u);  // the edge was subdivided
}

}  // namespace
}  // namespace rayaccel
