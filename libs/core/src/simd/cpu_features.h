/// \file cpu_features.h
/// \brief Which vector instructions the kernels of simd/ may use (internal to dlo_core).
///
/// SSE2 is part of x86-64, so its kernels are chosen at compile time (`__SSE2__`). The build
/// targets plain x86-64, so AVX2 is asked of the processor at run time: its kernels are compiled
/// with `__attribute__((target("avx2")))` and exist where DLO_SIMD_AVX2_DISPATCH is defined.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__)
#define DLO_SIMD_AVX2_DISPATCH 1
#endif

namespace dlo::simd {

#ifdef DLO_SIMD_AVX2_DISPATCH
/// Whether this processor has AVX2, asked once.
inline bool hasAvx2() {
  static const bool has = __builtin_cpu_supports("avx2") != 0;
  return has;
}
#endif

}  // namespace dlo::simd
