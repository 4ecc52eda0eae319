// The primitives' run cut eight positions at a time (cutRingAvx2) against the run loop it
// replaces on AVX2 machines: the same run id at every position, the same runs, forest and counts,
// for rings of every length and start (not multiples of eight), any labels, and join bytes
// outside the ring (join[b] is never written by the extractor) that must be ignored.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "../../src/core/primitive_runs.hpp"

using namespace ring_curvature;

#if defined(RC_SIMD_CLONES_ON)
namespace
{
struct Cut
{
  std::vector<std::uint32_t> run, parent;
  std::vector<std::int32_t> comp;
  std::vector<PrimitiveExtractor::Run> runs;
  std::size_t num_runs;
};

// A run opens at b and wherever join is 0; a wanted label's run takes the next id, every other
// position gets `none` (as the run loop of primitives.cpp).
void referenceCut(std::uint32_t b, std::uint32_t e, const std::vector<Label>& lab,
                  const std::vector<std::uint8_t>& join, std::uint8_t num_wanted, std::uint32_t none, Cut& c)
{
  for (std::uint32_t p = b; p < e;)
  {
    const bool wanted = static_cast<std::uint8_t>(static_cast<std::uint8_t>(lab[p]) - 1) < num_wanted;
    std::uint32_t q = p + 1;
    while (q < e && join[q]) ++q;
    const auto id = static_cast<std::uint32_t>(c.num_runs);
    for (std::uint32_t r = p; r < q; ++r) c.run[r] = wanted ? id : none;
    if (wanted)
    {
      c.runs[c.num_runs] = {p, q, 0};
      c.parent[c.num_runs] = id;
      c.comp[c.num_runs] = 0;
      ++c.num_runs;
    }
    p = q;
  }
}
}  // namespace

TEST(PrimitiveRuns, EightAtATimeCutIsTheRunLoops)
{
  if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("popcnt")) GTEST_SKIP() << "no AVX2";
  std::mt19937 rng(5);
  const auto r = [&rng](std::uint32_t n) { return static_cast<std::uint32_t>(rng() % n); };
  const std::uint32_t m = 200;
  int checked = 0;
  for (int trial = 0; trial < 3000; ++trial)
  {
    const std::uint32_t b = r(40), e = b + r(60);  // e == b: an empty ring
    const auto num_wanted = static_cast<std::uint8_t>(r(2) ? 4 : 3);
    const std::uint32_t run_bias = r(4);  // from mostly single positions to long runs
    std::vector<Label> lab(m);
    std::vector<std::uint8_t> join(m + 16);
    for (auto& j : join) j = static_cast<std::uint8_t>(r(2));  // garbage outside the ring
    for (std::uint32_t p = b; p < e; ++p)
    {
      lab[p] = p > b && r(4) < run_bias ? lab[p - 1] : static_cast<Label>(r(5));
      const bool w = static_cast<std::uint8_t>(static_cast<std::uint8_t>(lab[p]) - 1) < num_wanted;
      // joins only where the extractor's angular test can join: same wanted label
      if (p > b) join[p] = w && lab[p] == lab[p - 1] && r(8) != 0;
    }
    const std::uint32_t none = m;
    const std::size_t first = r(5);
    Cut ref{std::vector<std::uint32_t>(m + 8, 7), std::vector<std::uint32_t>(m + 1, 9),
            std::vector<std::int32_t>(m + 1, 5), std::vector<PrimitiveExtractor::Run>(m), first};
    Cut got = ref;
    referenceCut(b, e, lab, join, num_wanted, none, ref);
    std::vector<std::uint32_t> begins(m + 8), ends(m + 8);
    got.num_runs = cutRingAvx2(b, e, lab.data(), join.data(), num_wanted, none, got.parent.data(), got.run.data(),
                               got.comp.data(), got.runs.data(), first, begins.data(), ends.data());
    ASSERT_EQ(got.num_runs, ref.num_runs) << "trial " << trial;
    for (std::uint32_t p = b; p < e; ++p) ASSERT_EQ(got.run[p], ref.run[p]) << "trial " << trial << " p " << p;
    for (std::size_t k = first; k < ref.num_runs; ++k)
    {
      ASSERT_EQ(got.runs[k].begin, ref.runs[k].begin) << "trial " << trial << " run " << k;
      ASSERT_EQ(got.runs[k].end, ref.runs[k].end) << "trial " << trial << " run " << k;
      ASSERT_EQ(got.parent[k], ref.parent[k]);
      ASSERT_EQ(got.comp[k], ref.comp[k]);
    }
    checked += static_cast<int>(ref.num_runs - first);
  }
  EXPECT_GT(checked, 10000);
}
#endif
