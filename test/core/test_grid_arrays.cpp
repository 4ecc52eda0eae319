// Scan grid arrays against their definitions: the nearest sample on the ring above, and the
// organized placement, gather and ring elevations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "../support/synthetic_cloud.hpp"
#include "ring_curvature/pipeline.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
constexpr double kDeg = 3.14159265358979323846 / 180;
}  // namespace

// The nearest sample on the ring above against its definition: of the last sample above at or
// before the azimuth (the ring's first when there is none), its successor (the ring's first
// after its last) and the ring's last one, the circularly nearest, the first of equals in that
// order. Rings of unlike densities (7 to 3600 samples), gaps of every length on both rings,
// shifted starts and an empty ring: the grouped search must fall back wherever its window of
// sixteen samples above does not hold the answer.
TEST(ScanGrid, VerticalNeighboursMatchTheirDefinition)
{
  constexpr double kPiD = 3.14159265358979323846;
  const int samples[] = {1800, 1800, 900, 1800, 60, 1800, 1790, 3600, 1800, 7, 1800, 1800, 0, 1800};
  const int rings = static_cast<int>(sizeof samples / sizeof samples[0]);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  SyntheticCloud c;
  for (int r = 0; r < rings; ++r)
  {
    const double step = 2 * kPiD / std::max(samples[r], 1);
    const double phi = (-10 + 1.5 * r) * kDeg;
    for (int k = 0; k < samples[r]; ++k)
    {
      if (u(rng) < 0.02)  // a gap: mostly a few samples, sometimes a long one
      {
        k += static_cast<int>(u(rng) * (u(rng) < 0.2 ? 200 : 12));
        continue;
      }
      const double az = -kPiD + (k + 0.3 * (u(rng) - 0.5) + 0.37 * r) * step;
      const double range = 5 + 10 * u(rng);
      c.add(range * std::cos(phi) * std::cos(az), range * std::cos(phi) * std::sin(az), range * std::sin(phi), r);
    }
  }
  Pipeline p;
  FrameResult res;
  ASSERT_TRUE(p.process(c.view(), res).ok);
  const ScanGrid& g = p.grid();
  ASSERT_EQ(g.num_rings, rings);
  ASSERT_EQ(g.up.size(), g.size());
  const auto circ = [](float d) {
    const float a = std::fabs(d);
    return a > 3.14159265358979f ? 6.28318530717959f - a : a;
  };
  std::size_t checked = 0;
  for (int n = 0; n < rings; ++n)
  {
    const std::uint32_t b = g.ring_begin[n], e = g.ring_begin[n + 1];
    const std::uint32_t ub = e, ue = n + 1 < rings ? g.ring_begin[n + 2] : e;
    EXPECT_GE(e - b, static_cast<std::uint32_t>(samples[n] / 2)) << n;  // nearly all kept
    for (std::uint32_t pos = b; pos < e; ++pos)
    {
      if (ub == ue)
      {
        EXPECT_EQ(g.up[pos], -1) << pos;
        continue;
      }
      const float a = g.azimuth[pos];
      std::uint32_t q = ub;
      for (std::uint32_t k = ub + 1; k < ue; ++k)
        if (g.azimuth[k] <= a) q = k;
      const std::uint32_t cand[3] = {q, q + 1 < ue ? q + 1 : ub, ue - 1};
      std::uint32_t best = cand[0];
      for (int j = 1; j < 3; ++j)
        if (circ(g.azimuth[cand[j]] - a) < circ(g.azimuth[best] - a)) best = cand[j];
      ASSERT_EQ(g.up[pos], static_cast<std::int32_t>(best)) << "ring " << n << " position " << pos;
      ++checked;
    }
  }
  EXPECT_GT(checked, 10000u);
}
