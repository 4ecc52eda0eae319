// Which of the core's forms pay on the CPU it runs on, beyond what the CPU supports: a tuning
// profile per vendor, chosen once.
//
// Gathers and masked stores. Some AVX2 forms lean on instructions that every AVX2 CPU has but
// not every one runs fast: the gathers (vpgatherdd, vgatherdps) and the masked loads and stores
// (vpmaskmovd). On Intel cores since Haswell they are a few micro-ops each, and the forms built
// on them were measured faster than the plain loops (docs/benchmark_history.md, sessions 5 to 10). On
// AMD Zen they are microcoded: on Zen 3 (session 11's host; in-process A/B against the forms
// with them) the primitives stage took 0.84-0.88 of its time without the index fill's masked
// stores, and the output stage in groups of eight (pipeline.cpp) 0.87-0.90 of the gathers' time
// on KITTI frames, 1.01 on VLP-16 dual-return ones and 1.02-1.05 on organized OS1-128 ones,
// where masked-off lanes (padding) make the gathers cheap. The input passes read their records
// with plain loads and shuffles there (input_avx2.hpp; grid 0.88 to 0.92 of the gather forms'
// on the KITTI, VLP-16 and OS1-128 frames). On Zen 4 (session 21; AVX-512, whose forms run first)
// the Intel profile took the primitives 1.13-1.22 of the AMD profile's time and the output stage
// 1.12-1.78 (KITTI, VLP-16, OS1-128 frames): the AMD profile holds there too, with an output
// form of its own for AVX-512 (pipeline.cpp).
//
// The outputs are the same bits under either profile; only the speed differs.
#pragma once

namespace ring_curvature
{
namespace detail
{

/// True where the AVX2 forms built on gathers and masked loads / stores should run: an AVX2 CPU
/// with the Intel profile.
bool avx2Gathers();

/// The profile in force and why, for the benchmarks' banner: "intel", "amd (AMD CPU)",
/// "amd (RC_CPU_TUNING=amd)", ... Every CPU but an AMD one gets the Intel profile (the one
/// sessions 1 to 10 tuned for). RC_CPU_TUNING=intel or =amd in the environment forces one (read
/// once, at the first call), so that the tests can run both profiles' forms on any host; any
/// other value is named here and ignored.
const char* cpuTuningName();

/// True where the hand-written AVX-512 forms run (input pass, fold, ring sort, vertical
/// neighbours and unions, run cut, chord ends, organized placement): a CPU with AVX-512F, unless
/// RC_CPU_AVX512=off in the environment (read once, at the first call) keeps them off. Then the
/// AVX2 forms run in their place, as on a CPU without AVX-512 (most laptops and desktops: the
/// paper's i7-12700 has none), so that they can be timed side by side and tested natively on an
/// AVX-512 host, or kept where AVX-512 lowers the clock. The outputs are the same bits either
/// way. The features' loops are target clones that the loader picks by the CPU alone
/// (simd_clones.hpp): those stay AVX-512 on an AVX-512 CPU.
bool avx512Forms();

/// For the banner: "" when RC_CPU_AVX512 is unset (or empty), "; AVX-512 forms off
/// (RC_CPU_AVX512=off)", or a note that a value other than off / on was ignored.
const char* avx512Note();

}  // namespace detail
}  // namespace ring_curvature
