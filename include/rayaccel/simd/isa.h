// The one CPU / instruction-set module: which vector instruction sets this CPU runs (checked once at run time, with
// GCC's __builtin_cpu_supports) and the target attributes that compile a function for each. Every structure picks
// its kernels' instruction set here and runs them through simd/dispatch.h.
#pragma once

/// 1 when this build has the eight-lane AVX kernels (Avx8 and Avx8Masked). Clang (checked with Clang 14)
/// rejects, as an ABI error rather than GCC's -Wpsabi note, every call that passes a 32-byte vector from the generic
/// lane code (compiled for the default target) to Avx8's target("avx2") operations, even when the caller is always
/// inlined into an AVX entry point. A Clang build therefore compiles the SSE kernels only: best_isa() answers sse2,
/// bvh_wide builds four-wide nodes and traces packets ray by ray, and answers are the same (every kernel performs the
/// scalar kernel's float operations); only speed differs. GCC builds have every kernel.
#if defined(__clang__)
#define RAYACCEL_AVX_KERNELS 0
#else
#define RAYACCEL_AVX_KERNELS 1
#endif

namespace rayaccel::simd {

/// Instruction set of the SIMD kernels, in increasing order. sse2: four lanes (every x86-64 CPU). avx2: eight
/// lanes. avx512: eight lanes compiled for AVX-512 (F, VL, DQ, BW), 32 vector registers, with the lane set
/// Avx8Masked (lanes_avx512.h): the AVX2 operations plus mask compares, compress and sorting, which the wide BVH's
/// traversal uses; the same results as avx2.
enum class Isa { sse2, avx2, avx512 };
/// "sse2", "avx2" or "avx512".
const char* to_string(Isa isa);

/// True when this CPU runs AVX2 code.
bool cpu_has_avx2();
/// True when this CPU runs code built with RAYACCEL_TARGET_AVX512 (AVX2 and AVX-512 F, VL, DQ, BW).
bool cpu_has_avx512();
/// The widest instruction set this CPU runs and this build has kernels for (see RAYACCEL_AVX_KERNELS), at most `cap`.
Isa best_isa(Isa cap = Isa::avx512);

}  // namespace rayaccel::simd

/// Function attributes compiling a function (and, with flatten, everything inlined into it) for one instruction set.
/// The AVX-512 feature list is the one cpu_has_avx512() checks (src/simd/isa.cpp).
#define RAYACCEL_TARGET_AVX2 __attribute__((target("avx2")))
#define RAYACCEL_TARGET_AVX512 __attribute__((target("avx2,avx512f,avx512vl,avx512dq,avx512bw")))
