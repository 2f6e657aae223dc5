// 63-bit Morton codes of centroids and a parallel sort by them (Lauterbach et al. 2009).
#include "rayaccel/bvh/morton.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>

#include "rayaccel/bvh/build_tree.h"

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

}  // namespace

std::vector<std::uint64_t> sort_by_morton_code(PrimRefs& refs) {
  const AABB centroids = centroid_bounds_of(refs);
  const Vec3 extent = centroids.extent();
  constexpr float kCells = 2097151.0f;  // 2^21 - 1
  Vec3 scale;
  for (int a = 0; a < 3; ++a) scale[a] = extent[a] > 0.0f ? kCells / extent[a] : 0.0f;
  struct Keyed {
    std::uint64_t code;
    std::uint32_t prim_id;
    std::uint32_t index;
  };
  std::vector<Keyed> keys(refs.size());
  tbb::parallel_for(std::size_t{0}, refs.size(), [&](std::size_t i) {
    const Vec3 c = refs[i].centroid();
    std::uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
      const float q = std::clamp((c[a] - centroids.lo[a]) * scale[a], 0.0f, kCells);
      code |= spread_bits(static_cast<std::uint64_t>(q)) << (2 - a);
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
