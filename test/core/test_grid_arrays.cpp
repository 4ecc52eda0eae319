// Scan grid arrays against their definitions: the nearest sample on the ring above, the
// organized placement, gather and ring elevations, and the unorganized grid positions, verdicts
// and ring elevations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "../support/synthetic_cloud.hpp"
#include "common/float_bits.hpp"
#include "ring_curvature/pipeline.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
constexpr double kDeg = 3.14159265358979323846 / 180;

// Ring r's elevation and cone cosine as the grid defines them: from the mean of its n samples'
// sines z / range, whose sum (in grid order) is `sines`.
void expectRingElevation(const ScanGrid& g, int r, double sines, std::uint32_t n)
{
  const double sine = n > 0 ? std::clamp(sines / n, -1.0, 1.0) : 0.0;
  EXPECT_EQ(g.ring_elevation[r], static_cast<float>(std::asin(sine))) << r;
  EXPECT_EQ(g.ring_cos[r], static_cast<float>(std::sqrt(1.0 - sine * sine))) << r;
}
}  // namespace

// The nearest sample on the ring above against its definition: of the last sample above at or
// before the azimuth (the ring's first when there is none), its successor (the ring's first
// after its last) and the ring's last one, the circularly nearest, the first of equals in that
// order; `below`, the last sample below at or before the azimuth, likewise. Rings of unlike densities (7 to 3600 samples), gaps of every length on both rings,
// shifted starts and an empty ring, and an 1800-sample ring under a 3600 one (the walk moves
// two samples above for one below).
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
  ASSERT_EQ(g.below.size(), g.size());
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
    const std::uint32_t bb = n > 0 ? g.ring_begin[n - 1] : b;
    for (std::uint32_t pos = b; pos < e; ++pos)
    {
      // below: the last position on the ring below at or before the azimuth (its first if none)
      std::int32_t last = bb < b ? static_cast<std::int32_t>(bb) : -1;
      for (std::uint32_t k = bb + 1; k < b; ++k)
        if (g.azimuth[k] <= g.azimuth[pos]) last = static_cast<std::int32_t>(k);
      ASSERT_EQ(g.below[pos], last) << "ring " << n << " position " << pos;
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

// Organized float32 frames, placed, gathered and summed: every array against the input, with
// rows all valid, all missing, and mixed (NaN, too near, the origin), in a width that is no
// multiple of 8.
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
    expectRingElevation(g, r, s, pos - g.ring_begin[r]);
  }
  EXPECT_EQ(g.size(), pos);
}

namespace
{
// One return of a sample
struct Return
{
  double x, y, z;
  bool nan;
};
// returns[r][k]: the first, second and third returns of sample k of ring r (empty: none)
using Returns = std::vector<std::vector<std::vector<Return>>>;

// Rings of `samples` samples each (the ring's size may be 0), clockwise at their own azimuth
// step from shifted starts: every sample a first return (3 % NaN), most with an identical copy
// (folded) or a second return 0.5 m further (off the grid), some of those with a third, a copy
// of the first or 0.3 m further still.
Returns interleavedReturns(const std::vector<int>& samples)
{
  constexpr double kPiD = 3.14159265358979323846;
  const int rings = static_cast<int>(samples.size());
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Returns returns(rings);
  for (int r = 0; r < rings; ++r)
  {
    const double step = 2 * kPiD / std::max(samples[r], 1), phi = (-15 + 1.6 * r) * kDeg;
    for (int k = 0; k < samples[r]; ++k)
    {
      const double az = kPiD - (k + 0.3 * (u(rng) - 0.5) + 0.37 * r) * step;  // clockwise
      const double range = 5 + 10 * u(rng), far = range + 0.5;
      const auto at = [&](double d, bool nan) {
        return Return{d * std::cos(phi) * std::cos(az), d * std::cos(phi) * std::sin(az), d * std::sin(phi), nan};
      };
      std::vector<Return> f{at(range, u(rng) < 0.03)};
      const double v = u(rng);
      if (v < 0.55) f.push_back(f[0]);  // an identical copy: folded
      else if (v < 0.75) f.push_back(at(far, false));  // a second return off the grid
      if (f.size() == 2 && u(rng) < 0.15) f.push_back(u(rng) < 0.7 ? f[0] : at(far + 0.3, false));
      returns[r].push_back(f);
    }
  }
  return returns;
}

// A return: its ring, sample and rank (0: first, 1: second, 2: third)
struct Id
{
  int ring, k, rank;
};

// Velodyne's dual-return firing order: a firing's first returns of every ring, then its second
// returns, then its thirds
std::vector<Id> firingOrder(const Returns& returns)
{
  const int rings = static_cast<int>(returns.size());
  int longest = 0;
  for (int r = 0; r < rings; ++r) longest = std::max(longest, static_cast<int>(returns[r].size()));
  std::vector<Id> fired;
  for (int k = 0; k < longest; ++k)
    for (int rank = 0; rank < 3; ++rank)
      for (int r = 0; r < rings; ++r)
        if (k < static_cast<int>(returns[r].size()) && rank < static_cast<int>(returns[r][k].size()))
          fired.push_back({r, k, rank});
  return fired;
}

// The same returns ring after ring, each sample's returns in turn
std::vector<Id> ringAfterRing(const Returns& returns)
{
  std::vector<Id> ring_order;
  for (int r = 0; r < static_cast<int>(returns.size()); ++r)
    for (int k = 0; k < static_cast<int>(returns[r].size()); ++k)
      for (int rank = 0; rank < static_cast<int>(returns[r][k].size()); ++rank) ring_order.push_back({r, k, rank});
  return ring_order;
}

// The cloud of the returns in `order`
SyntheticCloud cloudOf(const Returns& returns, const std::vector<Id>& order)
{
  SyntheticCloud c;
  for (const Id& id : order)
  {
    const Return& q = returns[id.ring][id.k][id.rank];
    if (q.nan)
      c.addNaN(id.ring);
    else
      c.add(q.x, q.y, q.z, id.ring);
  }
  return c;
}

// Where each return of `fired` sits in `ring_order` (each ring keeps its returns' order in both)
std::vector<std::size_t> inRingOrder(const std::vector<Id>& fired, const std::vector<Id>& ring_order, int rings)
{
  std::vector<std::size_t> in_ring_order(fired.size());
  std::vector<std::size_t> first_of_ring(rings + 1, 0);
  for (const Id& id : ring_order) ++first_of_ring[id.ring + 1];
  for (int r = 0; r < rings; ++r) first_of_ring[r + 1] += first_of_ring[r];
  std::vector<std::size_t> seen(rings, 0);
  for (std::size_t i = 0; i < fired.size(); ++i)
    in_ring_order[i] = first_of_ring[fired[i].ring] + seen[fired[i].ring]++;
  return in_ring_order;
}
}  // namespace

// Unorganized rings interleaved point by point (velodyne's dual-return firing order: a firing's
// first returns of every ring, then its second returns, then a few thirds): the grid positions,
// the verdicts of the folded copies (resolved by blocks of the input, the rings' lists side by
// side, each in its order) and each ring's elevation against their definitions and against the
// same points sent ring after ring (one list of folded copies, in input order). 19 rings of
// unlike sizes, empty and single-point ones and NaN returns among them, so that the rings' lists
// end in different blocks; third returns that follow a folded copy.
TEST(ScanGrid, InterleavedRingsMatchTheirDefinitionsAndRingAfterRing)
{
  const std::vector<int> samples = {900, 905, 899, 1400, 3, 0, 1, 7, 900, 902, 450, 900, 900, 1200, 901, 903, 5, 900, 17};
  const int rings = static_cast<int>(samples.size());
  const Returns returns = interleavedReturns(samples);
  const std::vector<Id> fired = firingOrder(returns), ring_order = ringAfterRing(returns);  // the two input orders
  const SyntheticCloud cf = cloudOf(returns, fired), cr = cloudOf(returns, ring_order);
  Pipeline pf, pr;
  FrameResult rf, rr;
  ASSERT_TRUE(pf.process(cf.view(), rf).ok);
  ASSERT_TRUE(pr.process(cr.view(), rr).ok);
  const ScanGrid &g = pf.grid(), &gr = pr.grid();
  ASSERT_EQ(g.num_rings, rings);
  EXPECT_GT(g.num_folded, fired.size() / 4);  // most identical copies were folded
  EXPECT_GT(g.num_second_returns, 1000u);
  // every grid position, and each ring's elevation from its sines summed in grid order
  for (std::uint32_t p = 0; p < g.size(); ++p) ASSERT_EQ(g.grid_pos[g.index[p]], static_cast<std::int32_t>(p)) << p;
  for (int r = 0; r < rings; ++r)
  {
    const std::uint32_t b = g.ring_begin[r], e = g.ring_begin[r + 1];
    double s = 0;
    for (std::uint32_t p = b; p < e; ++p) s += g.z[p] / g.range[p];
    expectRingElevation(g, r, s, e - b);
    EXPECT_EQ(g.ring_elevation[r], gr.ring_elevation[r]) << r;
  }
  // Each point's state and grid position are those of the same point sent ring after ring (the
  // grids hold the same points in the same order: each ring keeps its points' order in both).
  ASSERT_EQ(g.size(), gr.size());
  const std::vector<std::size_t> in_ring_order = inRingOrder(fired, ring_order, rings);
  std::size_t duplicates = 0;
  for (std::size_t i = 0; i < fired.size(); ++i)
  {
    const std::size_t j = in_ring_order[i];
    ASSERT_EQ(static_cast<int>(g.state[i]), static_cast<int>(gr.state[j])) << i;
    ASSERT_EQ(g.grid_pos[i], gr.grid_pos[j]) << i;
    duplicates += g.state[i] == PointState::Duplicate ? 1 : 0;
  }
  EXPECT_EQ(g.num_duplicates, duplicates);
  EXPECT_EQ(g.num_duplicates, gr.num_duplicates);
  EXPECT_EQ(g.num_second_returns, gr.num_second_returns);
  EXPECT_EQ(rf.label, [&] {
    std::vector<std::uint8_t> l(fired.size());
    for (std::size_t i = 0; i < fired.size(); ++i) l[i] = rr.label[in_ring_order[i]];
    return l;
  }());
}
