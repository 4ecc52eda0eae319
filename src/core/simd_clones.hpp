// RC_SIMD_CLONES: compile a hot loop's function twice, for the x86-64 baseline and for AVX2, and
// pick one at load time by the CPU (GCC function multiversioning, an ifunc). The package stays a
// portable baseline build; a CPU with AVX2 runs the gathers and 4-wide doubles its loops need.
// Only AVX2 is enabled, not FMA: fused multiply-adds would round differently, and both versions
// must give the same bits. Elsewhere (other compilers, other architectures) it expands to nothing,
// and so it does with the CMake option RC_SIMD_CLONES=OFF, which is how the two versions are
// checked against each other (docs/benchmark.md, "Reproduce").
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && !defined(RC_NO_SIMD_CLONES)
#define RC_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
// The feature kernels also for AVX-512 (sixteen floats a vector since they run in float32): the
// stage took 0.77-0.89 of its AVX2 time (in-process A/B, KITTI and VLP-16 frames). Not the other
// stages: there it gained nothing, and the classification lost 4-6 %. AVX-512F brings FMA, which
// the core builds with -ffp-contract=off (cmake/core.cmake), so the bits stay the baseline's.
#define RC_SIMD_CLONES_WIDE __attribute__((target_clones("avx512f", "avx2", "default")))
#define RC_SIMD_CLONES_ON 1
// Around the hand-written AVX-512 functions: GCC 12's AVX-512 intrinsics pass
// _mm512_undefined_*() as the unused source of their masked builtins, which -Wmaybe-uninitialized
// reports once they are inlined (a known false positive). Off between these two alone.
#define RC_AVX512_BEGIN _Pragma("GCC diagnostic push") _Pragma("GCC diagnostic ignored \"-Wmaybe-uninitialized\"")
#define RC_AVX512_END _Pragma("GCC diagnostic pop")
#else
#define RC_SIMD_CLONES
#define RC_SIMD_CLONES_WIDE
#endif
