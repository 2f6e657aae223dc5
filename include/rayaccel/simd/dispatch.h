// The one instruction-set dispatch every SIMD structure uses: runs a generic body with the lane set of the chosen
// Isa, inside an entry point compiled for that instruction set (target attribute plus flatten, so the body and every
// RAYACCEL_LANE_INLINE kernel it calls are compiled there, see lane_set.h).
#pragma once

#include "rayaccel/simd/isa.h"
#include "rayaccel/simd/lane_set.h"
#include "rayaccel/simd/lanes_sse.h"
#if RAYACCEL_AVX_KERNELS
#include "rayaccel/simd/lanes_avx2.h"
#include "rayaccel/simd/lanes_avx512.h"
#endif

namespace rayaccel::simd {

namespace detail {
// Entry points: one per instruction set. The body is a generic lambda `[&]<class Lanes>() RAYACCEL_LANE_LAMBDA {...}`.
template <class Body>
__attribute__((flatten)) void run_sse2(const Body& body) {
  body.template operator()<Sse4>();
}
#if RAYACCEL_AVX_KERNELS
template <class Body>
RAYACCEL_TARGET_AVX2 __attribute__((flatten)) void run_avx2(const Body& body) {
  body.template operator()<Avx8>();
}
template <class Body>
RAYACCEL_TARGET_AVX512 __attribute__((flatten)) void run_avx512(const Body& body) {
  body.template operator()<Avx8Masked>();
}
#endif
}  // namespace detail

/// Runs body.operator()<Lanes>() with Lanes = Sse4 for Isa::sse2, Avx8 for avx2 and Avx8Masked for avx512, compiled
/// for `isa` (which the caller chose with best_isa(Cap), so this CPU runs it; without RAYACCEL_AVX_KERNELS that is
/// always sse2). `Cap` is the widest instruction set the caller ever picks: entry points above it are not
/// instantiated (the kd-tree and the grid cap at AVX2, so no AVX-512 copy of their traversal is compiled into every
/// binary); an isa above Cap runs at Cap.
template <Isa Cap = Isa::avx512, class Body>
inline void run_with_lanes(Isa isa, const Body& body) {
#if RAYACCEL_AVX_KERNELS
  switch (isa) {
    case Isa::avx512:
      if constexpr (Cap == Isa::avx512) {
        detail::run_avx512(body);
        return;
      }
      [[fallthrough]];
    case Isa::avx2:
      if constexpr (Cap != Isa::sse2) {
        detail::run_avx2(body);
        return;
      }
      [[fallthrough]];
    case Isa::sse2:
      break;
  }
#else
  (void)isa;
#endif
  detail::run_sse2(body);
}

}  // namespace rayaccel::simd
