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
// sixteen samples above (32 for the sixteen-lane AVX-512 form) does not hold the answer. A
// 1800-sample ring under a 3600 one carries the AVX-512 form's count to 32.
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

// Organized float32 frames are placed, gathered and summed in one pass (eight columns at a time
// on AVX2): every array against the input, with rows all valid, all missing, and mixed (NaN,
// too near, the origin), in a width that is no multiple of 8.
TEST(ScanGrid, OrganizedGridMatchesItsInput)
{
  const int rows = 5, cols = 203;
  const double nan = std::numeric_limits<double>::quiet_NaN(), skip[rows] = {0.0, 1.0, 0.3, 0.5, 0.9};
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  SyntheticCloud org;
  std::vector<float> xyz;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
    {
      const double k = u(rng) < skip[r] ? (c % 3 == 0 ? nan : c % 3 == 1 ? 0.01 : 0.0) : 1 + 30 * u(rng);
      const double az = 2 * 3.14159265 * c / cols, el = (u(rng) - 0.5) * 0.4;
      org.add(k * std::cos(el) * std::cos(az), k * std::cos(el) * std::sin(az), k * std::sin(el), r);
      for (double v : {k * std::cos(el) * std::cos(az), k * std::cos(el) * std::sin(az), k * std::sin(el)})
        xyz.push_back(static_cast<float>(v));
    }
  Pipeline p;
  FrameResult res;
  ASSERT_TRUE(p.process(org.view(rows), res).ok);
  const ScanGrid& g = p.grid();
  std::uint32_t pos = 0;
  for (int r = 0; r < rows; ++r)
  {
    double s = 0;
    ASSERT_EQ(g.ring_begin[r], pos);
    for (std::uint32_t i = r * cols; i < static_cast<std::uint32_t>((r + 1) * cols); ++i)
    {
      const double x = xyz[3 * i], y = xyz[3 * i + 1], z = xyz[3 * i + 2], range = std::sqrt(x * x + y * y + z * z);
      const bool valid = range >= p.params().min_range && range <= p.params().max_range;
      ASSERT_EQ(g.grid_pos[i], valid ? static_cast<std::int32_t>(pos) : -1) << i;
      if (!valid) continue;
      ASSERT_EQ(g.index[pos], i);
      EXPECT_TRUE(g.x[pos] == x && g.y[pos] == y && g.z[pos] == z && g.range[pos] == range) << i;
      EXPECT_EQ(g.azimuth[pos], fastAtan2(xyz[3 * i + 1], xyz[3 * i])) << i;
      s += z / range;
      ++pos;
    }
    const std::uint32_t n = pos - g.ring_begin[r];
    const double sine = n > 0 ? std::clamp(s / n, -1.0, 1.0) : 0.0;
    EXPECT_EQ(g.ring_elevation[r], static_cast<float>(std::asin(sine))) << r;
    EXPECT_EQ(g.ring_cos[r], static_cast<float>(std::sqrt(1.0 - sine * sine))) << r;
  }
  EXPECT_EQ(g.size(), pos);
}
