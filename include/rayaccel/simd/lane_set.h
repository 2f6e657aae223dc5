// The lane-set concept the SIMD kernels are written over (Sse4: lanes_sse.h, Avx8: lanes_avx2.h), and the one rule
// that makes generic lane code safe at every optimisation level (RAYACCEL_LANE_INLINE, below).
#pragma once

#include <concepts>

/// Generic code over a lane set is compiled once, for the default target, yet with Avx8 it handles 32-byte vectors,
/// which the x86-64 ABI passes in registers only between functions built with AVX (in memory otherwise). Avx8's
/// operations carry target("avx2"), so a call from a generic function that was not inlined into an AVX function
/// passes its vectors one way and reads them the other: wrong answers or a crash. Every generic function that takes,
/// returns or computes lane values therefore carries RAYACCEL_LANE_INLINE, so it is always inlined, also at -O0, into
/// the AVX entry point that simd/dispatch.h compiles for the chosen instruction set; no such vector then crosses a
/// call between different targets, and GCC's -Wpsabi note on it does not apply (RAYACCEL_LANE_CODE_BEGIN/END silence
/// it around lane code).
#define RAYACCEL_LANE_INLINE [[gnu::always_inline]] inline
/// For lambdas in lane code: placed after the parameter list.
#define RAYACCEL_LANE_LAMBDA __attribute__((always_inline))
#define RAYACCEL_LANE_CODE_BEGIN _Pragma("GCC diagnostic push") _Pragma("GCC diagnostic ignored \"-Wpsabi\"")
#define RAYACCEL_LANE_CODE_END _Pragma("GCC diagnostic pop")

namespace rayaccel::simd {

/// A set of kWidth float lanes with the operations the box and triangle kernels use (compare results are all-ones
/// or all-zero lanes; movemask gives one bit a lane).
template <class S>
concept LaneSet = requires(typename S::F a, const float* p, float* q) {
  { S::kWidth } -> std::convertible_to<int>;
  { S::set1(0.0f) } -> std::same_as<typename S::F>;
  { S::zero() } -> std::same_as<typename S::F>;
  { S::add(a, a) } -> std::same_as<typename S::F>;
  { S::mul(a, a) } -> std::same_as<typename S::F>;
  { S::div(a, a) } -> std::same_as<typename S::F>;
  { S::min(a, a) } -> std::same_as<typename S::F>;
  { S::max(a, a) } -> std::same_as<typename S::F>;
  { S::le(a, a) } -> std::same_as<typename S::F>;
  { S::and_not(a, a) } -> std::same_as<typename S::F>;
  { S::load(p) } -> std::same_as<typename S::F>;
  { S::movemask(a) } -> std::same_as<int>;
  S::store(q, a);
};

}  // namespace rayaccel::simd
