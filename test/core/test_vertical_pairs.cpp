// The vertical unions' AVX-512 form (verticalPairsAvx512, vertical_pairs.hpp) against the tests
// of the loop it replaces, position by position: the same run pairs in the same order, for
// rings of every length and start, samples above that step along the ring (the window of
// sixteen), jump (the one-at-a-time blocks), wrap at the seam or are missing, ranges on both
// sides of Eq 20's tolerance, azimuths across +-pi, organized or not. Skipped on CPUs without
// AVX-512F, DQ, BW and VL (and under valgrind, which reports none).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "../../src/core/angles.hpp"
#include "../../src/core/proximity.hpp"
#include "../../src/core/vertical_pairs.hpp"

using namespace ring_curvature;

#if defined(RC_SIMD_CLONES_ON)
namespace
{
// The first of up, the one before, the one after (in the ring above, with its seam) that has
// p's label and is close by primitives.cpp's Eq 19-20 (proximity.hpp); none if none is.
std::uint32_t referenceRunAbove(const VerticalRing& V, double range_ratio, std::uint32_t p, std::uint32_t none)
{
  if (V.up[p] < 0 || V.run[p] == none) return none;
  const auto u = static_cast<std::uint32_t>(V.up[p]);
  const std::uint32_t cand[3] = {u, u > V.b ? u - 1 : V.e - 1, u + 1 < V.e ? u + 1 : V.b};
  for (int k = 0; k < 3; ++k)
  {
    const std::uint32_t q = cand[k];
    const bool azimuth_ok = (k == 0 && V.organized) || angDiff(V.azimuth[p], V.azimuth[q]) <= V.az_tol;
    if (inRange(V.range[p], V.range[q], range_ratio, V.range_min) && V.lab[q] == V.lab[p] && azimuth_ok)
      return V.run[q];
  }
  return none;
}
}  // namespace

TEST(VerticalPairs, EightAtATimeAreTheLoopsTests)
{
  if (!verticalPairsRuns()) GTEST_SKIP() << "no AVX-512F, DQ, BW and VL";
  std::mt19937 rng(11);
  const auto r = [&rng](std::uint32_t n) { return static_cast<std::uint32_t>(rng() % n); };
  const auto u01 = [&rng]() { return std::uniform_real_distribution<double>(0, 1)(rng); };
  std::size_t listed = 0, positions = 0;
  for (int trial = 0; trial < 4000; ++trial)
  {
    const std::uint32_t b0 = r(30), e0 = b0 + r(70), b = e0 + r(3), e = b + 1 + r(70), m = e + r(20);
    const std::uint32_t none = m;
    const auto num_wanted = static_cast<std::uint8_t>(r(2) ? 4 : 3);
    const bool organized = r(2) != 0;
    const double range_ratio = 0.02 + 0.1 * u01(), range_min = 0.05 * u01();
    const float az_tol = static_cast<float>(0.002 + 0.02 * u01());
    std::vector<Label> lab(m);
    std::vector<std::uint32_t> run(m + 16, 3 * m);  // garbage outside the rings
    std::vector<std::int32_t> up(m, -7);
    std::vector<double> range(m, std::nan(""));
    std::vector<float> azimuth(m, std::nanf(""));
    // labels in stretches, ranges near a level that moves slowly (walls) or jumps (ground
    // steps), azimuths anywhere
    const std::uint32_t stretch = 1 + r(8);
    double level = 2 + 30 * u01();
    for (std::uint32_t p = 0; p < m; ++p)
    {
      lab[p] = p > 0 && r(stretch) != 0 ? lab[p - 1] : static_cast<Label>(r(5));
      if (r(10) == 0) level = 2 + 30 * u01();
      range[p] = level * (1 + 0.08 * (u01() - 0.5));
      azimuth[p] = static_cast<float>(-kPiD + 2 * kPiD * u01());
    }
    // the sample above steps along the ring above; most positions take its label, a range and
    // an azimuth near it
    const std::uint32_t n_above = e - b;
    for (std::uint32_t p = b0; p < e0; ++p)
    {
      const double at = static_cast<double>(p - b0) / std::max<std::uint32_t>(1, e0 - b0);
      auto u = static_cast<std::int32_t>(b + static_cast<std::uint32_t>(at * n_above) % n_above);
      const std::uint32_t kind = r(40);
      if (kind == 0) u = -1;                                                    // nothing above
      else if (kind == 1) u = static_cast<std::int32_t>(b + r(n_above));        // a jump
      else if (kind == 2) u = static_cast<std::int32_t>(r(2) ? b : e - 1);      // the seam
      up[p] = u;
      if (u < 0) continue;
      const auto q = static_cast<std::uint32_t>(u) + r(3) - 1;  // or one beside it
      const std::uint32_t w = q < b || q >= e ? static_cast<std::uint32_t>(u) : q;
      if (r(4) != 0) lab[p] = lab[w];
      if (r(3) != 0) range[p] = range[w] * (1 + 0.2 * (u01() - 0.5));
      if (r(3) != 0)
      {
        const float a = azimuth[w] + static_cast<float>((u01() - 0.5) * 3 * az_tol);
        azimuth[p] = a > kPi ? a - kTwoPi : (a < -kPi ? a + kTwoPi : a);
      }
    }
    // run ids: a new one at every label change, none for unwanted labels (as cutRing numbers them)
    std::uint32_t next_id = r(5);
    for (std::uint32_t p = 0; p < m; ++p)
    {
      const bool wanted = static_cast<std::uint8_t>(static_cast<std::uint8_t>(lab[p]) - 1) < num_wanted;
      next_id += p == 0 || lab[p] != lab[p - 1] || r(16) == 0;
      if ((p >= b0 && p < e0) || (p >= b && p < e)) run[p] = wanted ? next_id : none;
    }
    const VerticalRing V{b, e, nullptr, lab.data(), up.data(), range.data(), azimuth.data(), organized,
                         range_ratio * 0.5, range_min, az_tol, run.data(), nullptr};
    std::vector<std::uint64_t> ref;
    std::uint64_t prev = kNoVerticalPair;
    for (std::uint32_t p = b0; p < e0; ++p)
    {
      const std::uint32_t rq = referenceRunAbove(V, range_ratio, p, none);
      const std::uint64_t pair = rq == none ? kNoVerticalPair : (run[p] | static_cast<std::uint64_t>(rq) << 32);
      if (pair != kNoVerticalPair && pair != prev) ref.push_back(pair);
      prev = pair;
    }
    std::vector<std::uint64_t> got(e0 - b0 + 16, 5);
    const std::size_t np = verticalPairsAvx512(V, b0, e0, none, got.data());
    ASSERT_EQ(np, ref.size()) << "trial " << trial;
    for (std::size_t i = 0; i < np; ++i) ASSERT_EQ(got[i], ref[i]) << "trial " << trial << " entry " << i;
    for (std::size_t i = np + 8; i < got.size(); ++i) ASSERT_EQ(got[i], 5u) << "trial " << trial << " past the room";
    listed += np;
    positions += e0 - b0;
  }
  EXPECT_GT(listed, positions / 10);
  EXPECT_LT(listed, positions / 2);
}
#endif
