// Which of the hand-written AVX2 forms pay on the CPU the core runs on, beyond what it supports.
// Some forms lean on instructions that every AVX2 CPU has but not every one runs fast: the
// gathers (vpgatherdd, vgatherdps) and the masked loads and stores (vpmaskmovd). On Intel cores
// since Haswell they are a few micro-ops each and the forms built on them were measured faster
// than the plain loops (docs/benchmark.md, sessions 5 to 10). On AMD Zen they are microcoded:
// on Zen 3 (session 11's host; in-process A/B against the forms with them) the primitives stage
// took 0.84-0.88 of its time without the index fill's masked stores, and the output stage in
// groups of eight (pipeline.cpp) 0.87-0.90 of the gathers' time on KITTI frames, 1.01 on VLP-16
// dual-return ones and 1.02-1.05 on organized OS1-128 ones, where masked-off lanes (padding)
// make the gathers cheap. There the plain or unmasked forms run instead.
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
