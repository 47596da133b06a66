// Internal to the core: function multi-versioning for the row loops that the
// compiler vectorises.
#pragma once

// With GCC on x86-64, a function marked RISAS_VECTOR_CLONES is compiled
// three times, for the x86-64 baseline (SSE2, four floats per instruction),
// for AVX2 (eight) and for x86-64-v4 (AVX-512), and the loader picks the
// copy the CPU runs. All copies do the same arithmetic in the same order (the
// loops are element-wise, and the core is compiled with -ffp-contract=off:
// no fused multiply-adds), so results do not depend on the CPU.
// (GCC 11 is the first to know x86-64-v4; older compilers and others build
// the baseline copy only.) Under ThreadSanitizer too: the loader runs the
// copies' resolver before the TSan runtime starts, and the instrumented
// resolver then crashes every program that loads the library (GCC 12;
// llvm/llvm-project#163369 is the same with clang).
//
// A test build may compile the AVX2 copy alone (CMake's RISAS_ROW_LOOPS_AVX2;
// the library then needs an AVX2 CPU): on a CPU that would pick the AVX-512
// copy, it runs the one most CPUs pick. CI's sanitize stage is such a build.
#if defined(RISAS_ROW_LOOPS_AVX2)
#define RISAS_VECTOR_CLONES __attribute__((target("avx2")))
#elif defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && __GNUC__ >= 11 && \
    !defined(__SANITIZE_THREAD__)
#define RISAS_VECTOR_CLONES __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#else
#define RISAS_VECTOR_CLONES
#endif
