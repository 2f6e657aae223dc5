// The one CPU / instruction-set module: which vector instruction sets this CPU runs (checked once at run time, with
// GCC's __builtin_cpu_supports) and the target attributes that compile a function for each. Every structure picks
// its kernels' instruction set here and runs them through simd/dispatch.h.
#pragma once

namespace rayaccel::simd {

/// Instruction set of the SIMD kernels, in increasing order. sse2: four lanes (every x86-64 CPU). avx2: eight
/// lanes. avx512: the same eight-lane AVX2 kernels compiled for AVX-512 (F, VL, DQ, BW): identical 256-bit
/// operations and results, EVEX-encoded, with 32 vector registers instead of 16, so per-ray constants stay in
/// registers.
enum class Isa { sse2, avx2, avx512 };
/// "sse2", "avx2" or "avx512".
const char* to_string(Isa isa);

/// True when this CPU runs AVX2 code.
bool cpu_has_avx2();
/// True when this CPU runs code built with RAYACCEL_TARGET_AVX512 (AVX2 and AVX-512 F, VL, DQ, BW).
bool cpu_has_avx512();
/// The widest instruction set this CPU runs, at most `cap`.
Isa best_isa(Isa cap = Isa::avx512);

}  // namespace rayaccel::simd

/// Function attributes compiling a function (and, with flatten, everything inlined into it) for one instruction set.
/// The AVX-512 feature list is the one cpu_has_avx512() checks (src/simd/isa.cpp).
#define RAYACCEL_TARGET_AVX2 __attribute__((target("avx2")))
#define RAYACCEL_TARGET_AVX512 __attribute__((target("avx2,avx512f,avx512vl,avx512dq,avx512bw")))
