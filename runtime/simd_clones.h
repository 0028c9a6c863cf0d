#pragma once
// PENSIGHT_SIMD_CLONES before a function with hot vectorisable loops: on x86-64 Linux it is
// compiled twice, for x86-64-v3 (AVX2, FMA) and for the baseline (SSE2) the build targets, and the
// loader picks the clone the CPU runs (ifunc), so one binary uses AVX2 where there is one.
// Elsewhere (aarch64: NEON is the baseline) it expands to nothing.
#if defined(__x86_64__) && defined(__linux__) && defined(__GNUC__) && !defined(__CUDACC__)
#define PENSIGHT_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define PENSIGHT_SIMD_CLONES
#endif
