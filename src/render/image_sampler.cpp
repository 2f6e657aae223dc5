// Uniform and adaptive corner sampling of an image (Whitted 1980; contrast after Mitchell 1987).
#include "rayaccel/render/image_sampler.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <utility>
#include <string>

#include "rayaccel/core/error.h"

namespace rayaccel {

namespace {

bool power_of_two(int n) { return n > 0 && (n & (n - 1)) == 0; }

float parse_number(std::string_view text, std::string_view what) {
  float value = 0.0f;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) {
    throw Error("--aa: " + std::string(what) + " '" + std::string(text) + "' is not a number");
  }
  return value;
}

/// Fine-grid points along one line of the image (a horizontal line of pixel edges across the whole width, or one
/// pixel's vertical edge), each traced at most once, by whichever pixel asks first.
struct SharedPoints {
  std::vector<Vec3> values;
  std::vector<std::uint8_t> known;
  void reset(std::size_t size) {
    values.resize(size);
    known.assign(size, 0);
  }
};

/// The samples of one pixel on the finest grid, (N + 1) x (N + 1) points, traced on demand. Points on its edges live
/// in the neighbours' shared lines (top, bottom: image-wide rows; left, right: columns handed along a pixel row), so
/// each point of the image is traced once.
class PixelSamples {
 public:
  PixelSamples(int px, int py, int fine, long long row_stride, const std::function<Vec3(float, float, std::uint64_t)>& sample,
               SharedPoints& top, SharedPoints& bottom, SharedPoints& left, SharedPoints& right)
      : px_(px), py_(py), fine_(fine), stride_(row_stride), sample_(sample), top_(top), bottom_(bottom), left_(left),
        right_(right) {
    own_.reset(static_cast<std::size_t>(fine + 1) * (fine + 1));
  }

  /// The sample at local fine-grid point (i, j).
  const Vec3& at(int i, int j) {
    const auto [line, k] = where(i, j);
    if (!line->known[k]) {
      const long long gx = static_cast<long long>(px_) * fine_ + i, gy = static_cast<long long>(py_) * fine_ + j;
      const float inv = 1.0f / static_cast<float>(fine_);
      line->values[k] = sample_(static_cast<float>(px_) + static_cast<float>(i) * inv,
                                static_cast<float>(py_) + static_cast<float>(j) * inv,
                                static_cast<std::uint64_t>(gy * stride_ + gx));
      line->known[k] = 1;
      const bool corner = (i == 0 || i == fine_) && (j == 0 || j == fine_);
      ++(corner ? corners_traced_ : traced_);
    }
    return line->values[k];
  }
  /// Points other than the pixel's corners that this pixel traced (a corner is counted as every pixel's own).
  std::uint32_t traced() const { return traced_; }
  /// Every point this pixel traced, corners included.
  std::uint32_t traced_all() const { return traced_ + corners_traced_; }

 private:
  std::pair<SharedPoints*, std::size_t> where(int i, int j) {
    const std::size_t row = static_cast<std::size_t>(px_) * fine_ + i;
    if (j == 0) return {&top_, row};
    if (j == fine_) return {&bottom_, row};
    if (i == 0) return {&left_, static_cast<std::size_t>(j)};
    if (i == fine_) return {&right_, static_cast<std::size_t>(j)};
    return {&own_, static_cast<std::size_t>(j) * (fine_ + 1) + i};
  }
  int px_, py_, fine_;
  long long stride_;
  const std::function<Vec3(float, float, std::uint64_t)>& sample_;
  SharedPoints &top_, &bottom_, &left_, &right_;
  SharedPoints own_;
  std::uint32_t traced_ = 0, corners_traced_ = 0;
};

Vec3 mean4(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) { return (a + b + c + d) * 0.25f; }

/// Value of the square with top-left fine-grid corner (i, j) and side `size` fine steps.
Vec3 adaptive_value(PixelSamples& s, int i, int j, int size, float threshold) {
  const Vec3 c[4] = {s.at(i, j), s.at(i + size, j), s.at(i, j + size), s.at(i + size, j + size)};
  if (size == 1 || contrast(c, 4) < threshold) return mean4(c[0], c[1], c[2], c[3]);
  const int half = size / 2;
  return mean4(adaptive_value(s, i, j, half, threshold), adaptive_value(s, i + half, j, half, threshold),
               adaptive_value(s, i, j + half, half, threshold), adaptive_value(s, i + half, j + half, half, threshold));
}

}  // namespace

AntiAliasing parse_anti_aliasing(std::string_view text) {
  AntiAliasing aa;
  const std::size_t colon = text.find(':');
  const std::string_view mode = text.substr(0, colon);
  if (mode == "uniform") {
    aa.mode = AntiAliasing::Mode::uniform;
  } else if (mode == "adaptive") {
    aa.mode = AntiAliasing::Mode::adaptive;
  } else {
    throw Error("--aa: '" + std::string(mode) + "' is not a sampling mode (known: uniform, adaptive)");
  }
  std::string_view rest = colon == std::string_view::npos ? std::string_view() : text.substr(colon + 1);
  while (!rest.empty()) {
    const std::size_t comma = rest.find(',');
    const std::string_view item = rest.substr(0, comma);
    rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
    const std::size_t eq = item.find('=');
    const std::string_view key = item.substr(0, eq);
    const std::string_view value = eq == std::string_view::npos ? std::string_view() : item.substr(eq + 1);
    if (aa.mode == AntiAliasing::Mode::uniform && key == "n") {
      aa.n = static_cast<int>(parse_number(value, "n"));
      if (!power_of_two(aa.n) || aa.n > 64 || static_cast<float>(aa.n) != parse_number(value, "n")) {
        throw Error("--aa: uniform n=" + std::string(value) + " is not a power of two from 1 to 64");
      }
    } else if (aa.mode == AntiAliasing::Mode::adaptive && key == "threshold") {
      aa.threshold = parse_number(value, "threshold");
      if (!(aa.threshold >= 0.0f && aa.threshold <= 1.0f)) {
        throw Error("--aa: threshold=" + std::string(value) + " is not in [0, 1]");
      }
    } else if (aa.mode == AntiAliasing::Mode::adaptive && key == "max_level") {
      const float level = parse_number(value, "max_level");
      if (!(level >= 0.0f && level <= 6.0f && level == static_cast<float>(static_cast<int>(level)))) {
        throw Error("--aa: max_level=" + std::string(value) + " is not an integer from 0 to 6");
      }
      aa.max_level = static_cast<int>(level);
    } else {
      throw Error("--aa: '" + std::string(item) + "' is not an option of " + std::string(mode) +
                  (aa.mode == AntiAliasing::Mode::uniform ? " (known: n)" : " (known: threshold, max_level)"));
    }
  }
  return aa;
}

int finest_subdivision(const AntiAliasing& aa) {
  return aa.mode == AntiAliasing::Mode::uniform ? aa.n : 1 << aa.max_level;
}

float contrast(const Vec3* colours, int count) {
  float worst = 0.0f;
  for (int axis = 0; axis < 3; ++axis) {
    float lo = colours[0][axis], hi = colours[0][axis];
    for (int k = 1; k < count; ++k) {
      lo = std::min(lo, colours[k][axis]);
      hi = std::max(hi, colours[k][axis]);
    }
    if (hi + lo > 0.0f) worst = std::max(worst, (hi - lo) / (hi + lo));
  }
  return worst;
}

SampledImage sample_image(int width, int height, const AntiAliasing& aa,
                          const std::function<Vec3(float, float, std::uint64_t)>& sample,
                          const std::function<void(float)>& progress) {
  if (width <= 0 || height <= 0) {
    throw Error("image sampling: bad size " + std::to_string(width) + "x" + std::to_string(height));
  }
  const int fine = finest_subdivision(aa);
  if (!power_of_two(fine) || fine > 64) throw Error("image sampling: subdivision " + std::to_string(fine));
  const long long stride = static_cast<long long>(width) * fine + 1;  // fine-grid points per image row

  SampledImage out;
  out.width = width;
  out.height = height;
  out.pixels.resize(static_cast<std::size_t>(width) * height);
  out.samples.resize(out.pixels.size());
  std::atomic<std::uint64_t> traced{0};
  const std::size_t line_size = static_cast<std::size_t>(width) * fine + 1;
  // Pixel row y reads and writes lines y and y + 1 of the chunk; rows of one parity run in parallel (no two share a
  // line), then the other parity, so a point on a line between two rows is traced by the first that needs it.
  constexpr int kRowsPerChunk = 16;  // progress is reported on the calling thread after each chunk of rows
  std::vector<SharedPoints> lines(kRowsPerChunk + 1);
  lines[0].reset(line_size);
  const auto pixel_row = [&](int y, SharedPoints& top, SharedPoints& bottom) {
    SharedPoints left, right;
    left.reset(static_cast<std::size_t>(fine) + 1);
    std::uint64_t row_traced = 0;
    for (int x = 0; x < width; ++x) {
      right.reset(static_cast<std::size_t>(fine) + 1);
      PixelSamples samples(x, y, fine, stride, sample, top, bottom, left, right);
      Vec3 value;
      if (aa.mode == AntiAliasing::Mode::adaptive) {
        value = adaptive_value(samples, 0, 0, fine, aa.threshold);
      } else {
        // Uniform: every sub-square, summed row by row in double (an independent order from the adaptive
        // recursion, so the two are compared, not copied).
        double sum[3] = {0.0, 0.0, 0.0};
        for (int j = 0; j < fine; ++j) {
          for (int i = 0; i < fine; ++i) {
            const Vec3 m =
                mean4(samples.at(i, j), samples.at(i + 1, j), samples.at(i, j + 1), samples.at(i + 1, j + 1));
            for (int a = 0; a < 3; ++a) sum[a] += m[a];
          }
        }
        const double n = static_cast<double>(fine) * fine;
        value = {static_cast<float>(sum[0] / n), static_cast<float>(sum[1] / n), static_cast<float>(sum[2] / n)};
      }
      const std::size_t p = static_cast<std::size_t>(y) * width + x;
      out.pixels[p] = value;
      out.samples[p] = 4 + samples.traced();
      row_traced += samples.traced_all();
      std::swap(left, right);
    }
    traced += row_traced;
  };
  for (int y0 = 0; y0 < height; y0 += kRowsPerChunk) {
    const int y1 = std::min(height, y0 + kRowsPerChunk);
    for (int y = y0 + 1; y <= y1; ++y) lines[static_cast<std::size_t>(y - y0)].reset(line_size);
    for (int parity = 0; parity < 2; ++parity) {
      const int count = (y1 - y0 - parity + 1) / 2;
      tbb::parallel_for(tbb::blocked_range<int>(0, std::max(count, 0), 1), [&](const tbb::blocked_range<int>& ks) {
        for (int k = ks.begin(); k != ks.end(); ++k) {
          const int y = y0 + parity + 2 * k;
          pixel_row(y, lines[static_cast<std::size_t>(y - y0)], lines[static_cast<std::size_t>(y - y0 + 1)]);
        }
      });
    }
    std::swap(lines[0], lines[static_cast<std::size_t>(y1 - y0)]);
    if (progress) progress(static_cast<float>(y1) / static_cast<float>(height));
  }
  out.sample_count = traced.load();
  return out;
}

}  // namespace rayaccel
