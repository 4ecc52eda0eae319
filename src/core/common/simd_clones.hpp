// RC_SIMD_CLONES: compile a hot loop's function twice, for the x86-64 baseline and for AVX2, and
// pick one at load time by the CPU (GCC function multiversioning, an ifunc). The package stays a
// portable baseline build; a CPU with AVX2 runs the wider vectors the compiler forms from the
// same portable code. Only AVX2 is enabled, not FMA: fused multiply-adds would round
// differently, and both versions must give the same bits (the core also builds with
// -ffp-contract=off, cmake/core_sources.cmake). Elsewhere (other compilers, AArch64 and other
// architectures) it expands to nothing, and so it does with the CMake option RC_SIMD_CLONES=OFF,
// which is how scripts/test.d/70-simd-clones checks the two versions against each other.
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && !defined(RC_NO_SIMD_CLONES)
#define RC_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#define RC_SIMD_CLONES_ON 1
#else
#define RC_SIMD_CLONES
#endif
