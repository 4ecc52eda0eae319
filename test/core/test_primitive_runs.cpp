// The primitives' run cut eight (cutRingAvx2) and sixteen (cutRingAvx512) positions at a time
// against the run loop they replace: the same run id at every position, the same runs, forest
// and counts, for rings of every length and start (not multiples of eight or sixteen), any
// labels, and join bytes outside the ring (join[b] is never written by the extractor) that must
// be ignored. And the index fill's AVX2 form against its plain loop.
#include <gtest/gtest.h>

#include <algorithm>
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
      c.runs[c.num_runs].begin = p;  // (rank: the caller's, not written)
      c.runs[c.num_runs].end = q;
      c.parent[c.num_runs] = id;
      c.comp[c.num_runs] = 0;
      ++c.num_runs;
    }
    p = q;
  }
}

using CutFn = std::size_t (*)(std::uint32_t, std::uint32_t, const Label*, const std::uint8_t*, std::uint8_t,
                              std::uint32_t, std::uint32_t*, std::uint32_t*, std::int32_t*, PrimitiveExtractor::Run*,
                              std::size_t, std::uint32_t*, std::uint32_t*);

void checkCut(CutFn cut)
{
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
    Cut ref{std::vector<std::uint32_t>(m + 16, 7), std::vector<std::uint32_t>(m + 1, 9),
            std::vector<std::int32_t>(m + 1, 5), std::vector<PrimitiveExtractor::Run>(m + 16, {11, 12, 13}), first};
    Cut got = ref;
    referenceCut(b, e, lab, join, num_wanted, none, ref);
    std::vector<std::uint32_t> begins(m + 16), ends(m + 16);
    got.num_runs = cut(b, e, lab.data(), join.data(), num_wanted, none, got.parent.data(), got.run.data(),
                       got.comp.data(), got.runs.data(), first, begins.data(), ends.data());
    ASSERT_EQ(got.num_runs, ref.num_runs) << "trial " << trial;
    for (std::uint32_t p = b; p < e; ++p) ASSERT_EQ(got.run[p], ref.run[p]) << "trial " << trial << " p " << p;
    // nothing before the ring, nor past the 15 entries the contract allows
    for (std::uint32_t p = 0; p < b; ++p) ASSERT_EQ(got.run[p], 7u) << "trial " << trial << " p " << p;
    for (std::uint32_t p = e + 15; p < m + 16; ++p) ASSERT_EQ(got.run[p], 7u) << "trial " << trial << " p " << p;
    for (std::size_t k = first; k < ref.num_runs; ++k)
    {
      ASSERT_EQ(got.runs[k].begin, ref.runs[k].begin) << "trial " << trial << " run " << k;
      ASSERT_EQ(got.runs[k].end, ref.runs[k].end) << "trial " << trial << " run " << k;
      ASSERT_EQ(got.parent[k], ref.parent[k]);
      ASSERT_EQ(got.comp[k], ref.comp[k]);
    }
    // nothing past the ring's runs (parent and comp of `none` may follow them), no rank written
    for (std::size_t k = 0; k < m + 1; ++k) ASSERT_EQ(got.parent[k], ref.parent[k]) << "trial " << trial;
    for (std::size_t k = 0; k < m + 1; ++k) ASSERT_EQ(got.comp[k], ref.comp[k]) << "trial " << trial;
    for (std::size_t k = 0; k < m + 16; ++k)
    {
      ASSERT_EQ(got.runs[k].begin, ref.runs[k].begin) << "trial " << trial << " run " << k;
      ASSERT_EQ(got.runs[k].end, ref.runs[k].end) << "trial " << trial << " run " << k;
      ASSERT_EQ(got.runs[k].rank, 13u) << "trial " << trial << " run " << k;
    }
    checked += static_cast<int>(ref.num_runs - first);
  }
  EXPECT_GT(checked, 10000);
}

using FillFn = void (*)(const PrimitiveExtractor::Run*, std::size_t, const std::uint32_t*, const std::int32_t*,
                        const std::uint32_t*, PrimitiveInfo*, const std::uint32_t*, std::uint32_t*, std::uint32_t*,
                        std::int32_t*, std::uint32_t);

// What the fill writes (the plain loop of extract, one position at a time): each reported run's
// input indices and grid positions at its primitive's slots, its id at its positions in of_grid,
// -1 everywhere else below m, and the primitives' lowest and highest rings.
void referenceFill(const std::vector<PrimitiveExtractor::Run>& runs, const std::vector<std::uint32_t>& parent,
                   const std::vector<std::int32_t>& comp, const std::vector<std::uint32_t>& ring_begin,
                   std::vector<PrimitiveInfo>& prims, const std::vector<std::uint32_t>& index,
                   std::vector<std::uint32_t>& indices, std::vector<std::uint32_t>& slot_pos,
                   std::vector<std::int32_t>& of_grid, std::uint32_t m)
{
  for (std::uint32_t p = 0; p < m; ++p) of_grid[p] = -1;
  for (std::size_t k = 0; k < runs.size(); ++k)
  {
    const std::int32_t id = comp[parent[k]];
    if (id < 0) continue;
    int n = 0;
    while (runs[k].begin >= ring_begin[n + 1]) ++n;
    PrimitiveInfo& pr = prims[id];
    if (runs[k].rank == 0) pr.ring_min = static_cast<std::uint16_t>(n);
    pr.ring_max = static_cast<std::uint16_t>(n);
    for (std::uint32_t p = runs[k].begin, q = pr.first + runs[k].rank; p < runs[k].end; ++p, ++q)
    {
      of_grid[p] = id;
      indices[q] = index[p];
      slot_pos[q] = p;
    }
  }
}

// Random runs in grid order (lengths 1 to 40, across multiples of eight and sixteen), with gaps
// (unwanted positions), some rejected (comp -1), the others spread over a few primitives.
void checkFill(FillFn fill)
{
  std::mt19937 rng(11);
  const auto r = [&rng](std::uint32_t n) { return static_cast<std::uint32_t>(rng() % n); };
  for (int trial = 0; trial < 500; ++trial)
  {
    const std::uint32_t m = 50 + r(400), num_prims = 1 + r(6);
    std::vector<PrimitiveExtractor::Run> runs;
    std::vector<std::int32_t> comp;
    std::vector<std::uint32_t> parent, size(num_prims, 0);
    for (std::uint32_t p = r(20); p < m;)
    {
      const std::uint32_t t = std::min(m, p + 1 + r(r(2) ? 40 : 8));
      const auto id = r(5) == 0 ? -1 : static_cast<std::int32_t>(r(num_prims));
      runs.push_back({p, t, id < 0 ? 0 : size[static_cast<std::size_t>(id)]});
      if (id >= 0) size[static_cast<std::size_t>(id)] += t - p;
      parent.push_back(static_cast<std::uint32_t>(comp.size()));
      comp.push_back(id);
      p = t + (r(3) == 0 ? r(30) : 0);
    }
    std::vector<PrimitiveInfo> prims(num_prims);
    std::uint32_t total = 0;
    for (std::uint32_t i = 0; i < num_prims; ++i)
    {
      prims[i].first = total;
      total += size[i];
    }
    std::vector<std::uint32_t> ring_begin{0};
    while (ring_begin.back() < m) ring_begin.push_back(std::min(m, ring_begin.back() + 1 + r(100)));
    std::vector<std::uint32_t> index(m);
    for (auto& i : index) i = static_cast<std::uint32_t>(rng());
    // sentinels past the ends: nothing beyond m, total
    std::vector<std::uint32_t> indices(total + 16, 3), slot_pos(total + 16, 4);
    std::vector<std::int32_t> of_grid(m + 16, 5);
    auto ref_prims = prims;
    auto ref_indices = indices, ref_slot_pos = slot_pos;
    auto ref_of_grid = of_grid;
    referenceFill(runs, parent, comp, ring_begin, ref_prims, index, ref_indices, ref_slot_pos, ref_of_grid, m);
    fill(runs.data(), runs.size(), parent.data(), comp.data(), ring_begin.data(), prims.data(), index.data(),
         indices.data(), slot_pos.data(), of_grid.data(), m);
    ASSERT_EQ(of_grid, ref_of_grid) << "trial " << trial;
    ASSERT_EQ(indices, ref_indices) << "trial " << trial;
    ASSERT_EQ(slot_pos, ref_slot_pos) << "trial " << trial;
    for (std::uint32_t i = 0; i < num_prims; ++i)
    {
      ASSERT_EQ(prims[i].ring_min, ref_prims[i].ring_min) << "trial " << trial;
      ASSERT_EQ(prims[i].ring_max, ref_prims[i].ring_max) << "trial " << trial;
    }
  }
}
}  // namespace

TEST(PrimitiveRuns, EightWideFillIsThePlainLoops)
{
  if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "no AVX2";
  checkFill(fillRunsAvx2);
}

TEST(PrimitiveRuns, EightAtATimeCutIsTheRunLoops)
{
  if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("popcnt")) GTEST_SKIP() << "no AVX2";
  checkCut(cutRingAvx2);
}

TEST(PrimitiveRuns, SixteenAtATimeCutIsTheRunLoops)
{
  if (!__builtin_cpu_supports("avx512f") || !__builtin_cpu_supports("popcnt")) GTEST_SKIP() << "no AVX-512F";
  checkCut(cutRingAvx512);
}
#endif
