// RC_SIMD_CLONES: compile a hot loop's function for the x86-64 baseline and for AVX2, picked at load
// time by the CPU (GCC function multiversioning), so the package stays a portable build. Only AVX2,
// not FMA: fused multiply-adds round differently, and both versions must give the same bits (the
// core also builds with -ffp-contract=off). Elsewhere (other compilers, AArch64) and with the CMake
// option RC_SIMD_CLONES=OFF it expands to nothing; scripts/test.d/70-simd-clones compares the two.
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && !defined(RC_NO_SIMD_CLONES)
#define RC_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#define RC_SIMD_CLONES_ON 1
#else
#define RC_SIMD_CLONES
#endif
