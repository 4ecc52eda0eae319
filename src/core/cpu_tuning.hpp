// Which of the hand-written AVX2 forms pay on the CPU the core runs on, beyond what it supports.
// Some forms lean on instructions that every AVX2 CPU has but not every one runs fast: the
// gathers (vpgatherdd, vgatherdps) and the masked loads and stores (vpmaskmovd). On Intel cores
// since Haswell they are a few micro-ops each and the forms built on them were measured faster
// than the plain loops (docs/benchmark.md, sessions 5 to 10). On AMD Zen they are microcoded and
// slow: on Zen 3 (this project's session 11 host) the output stage's gathers took 1.28 times
// the plain loop's time and the index fill's masked stores 1.19 times the primitives' stage
// (in-process A/B, KITTI frames), so there the plain or unmasked forms run instead.
// The outputs are the same bits either way; only the speed differs.
#pragma once

namespace ring_curvature
{
namespace detail
{

/// True where the AVX2 forms built on gathers and masked loads / stores should run: an AVX2 CPU
/// that is not an AMD one. RC_AVX2_GATHERS=1 or =0 in the environment forces it (read once, at
/// the first call), so that the tests can run both forms on any AVX2 host.
bool avx2Gathers();

/// For the benchmarks' banner: "on" or "off", and why ("off (AMD)", "on (RC_AVX2_GATHERS=1)").
const char* avx2GathersReason();

}  // namespace detail
}  // namespace ring_curvature
