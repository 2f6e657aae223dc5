// 63-bit Morton codes of centroids and a parallel sort by them (Lauterbach et al. 2009).
#include "rayaccel/bvh/morton.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <limits>


namespace rayaccel {

namespace {

/// Spreads the low 21 bits of v so that bit i moves to bit 3i.
std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1FFFFF;
  v = (v | v << 32) & 0x1F00000000FFFFull;
  v = (v | v << 16) & 0x1F0000FF0000FFull;
  v = (v | v << 8) & 0x100F00F00F00F00Full;
  v = (v | v << 4) & 0x10C30C30C30C30C3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

constexpr double kMortonCells = 2097151.0;  // 2^21 - 1 cells along each axis

/// A centroid coordinate in double: (lo + hi) / 2 in float overflows to infinity for a box near FLT_MAX.
double centroid_along(const PrimRef& r, int axis) {
  return 0.5 * (double(r.bounds.lo[axis]) + double(r.bounds.hi[axis]));
}

}  // namespace

std::vector<std::uint64_t> sort_by_morton_code(PrimRefs& refs) {
  // Quantised in double, like the SBVH's bins: a float extent of boxes from -FLT_MAX to FLT_MAX is infinite, and
  // (c - lo) * scale then gave NaN, whose cast to an integer is undefined (the fuzz tier found it).
  std::array<double, 3> lo{}, scale{};
  for (int a = 0; a < 3; ++a) {
    double min = std::numeric_limits<double>::infinity(), max = -min;
    for (const PrimRef& r : refs) {
      const double c = centroid_along(r, a);
      min = std::min(min, c);
      max = std::max(max, c);
    }
    lo[a] = min;
    scale[a] = max > min ? kMortonCells / (max - min) : 0.0;
  }
  struct Keyed {
    std::uint64_t code;
    std::uint32_t prim_id;
    std::uint32_t index;
  };
  std::vector<Keyed> keys(refs.size());
  tbb::parallel_for(std::size_t{0}, refs.size(), [&](std::size_t i) {
    std::uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
      const double q = (centroid_along(refs[i], a) - lo[a]) * scale[a];
      const double cell = q >= kMortonCells ? kMortonCells : q > 0.0 ? q : 0.0;  // a NaN lands in cell 0
      code |= spread_bits(static_cast<std::uint64_t>(cell)) << (2 - a);
    }
    keys[i] = {code, refs[i].prim_id, static_cast<std::uint32_t>(i)};
  });
  tbb::parallel_sort(keys.begin(), keys.end(), [](const Keyed& a, const Keyed& b) {
    return a.code < b.code || (a.code == b.code && a.prim_id < b.prim_id);
  });
  PrimRefs sorted(refs.size());
  std::vector<std::uint64_t> codes(refs.size());
  tbb::parallel_for(std::size_t{0}, refs.size(), [&](std::size_t i) {
    sorted[i] = refs[keys[i].index];
    codes[i] = keys[i].code;
  });
  refs = std::move(sorted);
  return codes;
}

}  // namespace rayaccel
