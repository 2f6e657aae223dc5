// CPU detection for the SIMD kernels (see simd/isa.h): each answer computed once.
#include "rayaccel/simd/isa.h"

namespace rayaccel::simd {

const char* to_string(Isa isa) {
  switch (isa) {
    case Isa::sse2:
      return "sse2";
    case Isa::avx2:
      return "avx2";
    case Isa::avx512:
      return "avx512";
  }
  return "?";
}

bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

bool cpu_has_avx512() {
  // The features of RAYACCEL_TARGET_AVX512.
  static const bool has = cpu_has_avx2() && __builtin_cpu_supports("avx512f") &&
                          __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq") &&
                          __builtin_cpu_supports("avx512bw");
  return has;
}

Isa best_isa(Isa cap) {
  if (!RAYACCEL_AVX_KERNELS) return Isa::sse2;
  if (cap >= Isa::avx512 && cpu_has_avx512()) return Isa::avx512;
  if (cap >= Isa::avx2 && cpu_has_avx2()) return Isa::avx2;
  return Isa::sse2;
}

}  // namespace rayaccel::simd
