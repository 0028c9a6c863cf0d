#pragma once
// PENSIGHT_SIMD_CLONES before a function with hot vectorisable loops: on x86-64 Linux it is
// compiled twice, for x86-64-v3 (AVX2, FMA) and for the baseline (SSE2) the build targets, and the
// loader picks the clone the CPU runs (ifunc), so one binary uses AVX2 where there is one.
// Elsewhere (aarch64: NEON is the baseline) it expands to nothing, and so it does under
// ThreadSanitizer, which instruments the clones' resolver: that runs while the loader relocates the
// binary, before TSan's runtime is set up, and crashes it (GCC 12).
#if defined(__x86_64__) && defined(__linux__) && defined(__GNUC__) && !defined(__CUDACC__) && \
    !defined(__SANITIZE_THREAD__)
#define PENSIGHT_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define PENSIGHT_SIMD_CLONES
#endif
