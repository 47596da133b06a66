// Internal to the core: function multi-versioning for the row loops that the
// compiler vectorises.
#pragma once

// With GCC on x86-64, a function marked RISAS_VECTOR_CLONES is compiled
// twice, for the x86-64 baseline (SSE2, four floats per instruction) and for
// AVX2 (eight), and the loader picks the copy the CPU runs. Both copies do
// the same arithmetic in the same order (the loops are element-wise, and the
// core is compiled with -ffp-contract=off: no fused multiply-adds), so
// results do not depend on the CPU.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define RISAS_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define RISAS_VECTOR_CLONES
#endif
