// The grid's measured azimuth resolution (grid_resolution.cpp): the kept spacing of rank n / 2,
// on both of its paths (a bracket from a sample; the selection over all) and at the bracket's edges.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "../support/ray_scene.hpp"
#include "grid/spacing_median.hpp"
#include "ring_curvature/pipeline.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
// The room of test_scan_grid (four walls around the sensor) on level ground, 16 beams at
// 0.2 deg steps.
ScannedFrame roomOnGround()
{
  return scan(squareRoom(-1.8), SensorModel::uniform(16, -15, 15, 0.2), 0.005, 3);
}

// The grid's constants, formed as it forms them (float).
constexpr float kPiF = 3.14159265358979f, kTwoPiF = 6.28318530717959f, kDegF = kPiF / 180.0f;

std::uint32_t bitsOf(float v)
{
  std::uint32_t u;
  std::memcpy(&u, &v, sizeof u);
  return u;
}

// The measured resolution as defined: the element of rank n / 2 of the n kept spacings (above
// 1e-5 rad, below 5 deg), as nth_element gives it.
float referenceMedian(const std::vector<float>& d, float none)
{
  std::vector<float> k;
  for (float v : d)
    if (v > 1e-5f && v < 5.0f * kDegF) k.push_back(v);
  if (k.empty()) return none;
  std::nth_element(k.begin(), k.begin() + static_cast<std::ptrdiff_t>(k.size() / 2), k.end());
  return k[k.size() / 2];
}
}  // namespace

TEST(GridResolution, MeasuredResolutionIsTheKeptSpacingOfRankHalf)
{
  // Frames of every size around the sample's threshold (8192 spacings) and of several kinds:
  // azimuth-like spacings tied in a few float steps, with duplicates, gaps, NaN and the two
  // limits; distinct values (a neighbour of rank n / 2 would differ); one value; two values one
  // float step apart split about evenly (the rank falls on the edge between them); mostly not
  // kept (the sample is too thin: the selection over all); a spread over decades (a bracket
  // hundreds of thousands of float steps wide, selected by more than one digit); values whose
  // low bits sit on the edges of the digits' buckets. Distinct values come with many of each limit.
  std::mt19937 rng(11);
  const float step = 0.2f * kDegF, quantum = 7.4505806e-9f;  // 2^-27, an azimuth's float step near 1 rad
  SpacingMedian median;
  for (std::size_t total : {0, 1, 700, 8191, 8192, 8199, 14870, 30001})
    for (int kind = 0; kind < 7; ++kind)
    {
      std::vector<float> d(total);
      std::binomial_distribution<int> tie(16, 0.5);
      std::uniform_real_distribution<float> unit(0.0f, 1.0f);
      for (float& v : d)
      {
        const float u = unit(rng);
        switch (kind)
        {
          case 0:
            v = step + quantum * static_cast<float>(tie(rng) - 8);
            if (u < 0.03f) v = 0.0f;  // duplicates
            else if (u < 0.04f) v = 0.2f;  // gaps
            else if (u < 0.045f) v = u < 0.0425f ? 1e-5f : 5.0f * kDegF;  // the limits, not kept
            else if (u < 0.046f) v = std::numeric_limits<float>::quiet_NaN();
            break;
          case 1: v = u < 0.1f ? 1e-5f : (u < 0.15f ? 5.0f * kDegF : step * (0.5f + u)); break;
          case 2: v = u < 0.1f ? 0.0f : step; break;
          case 3: v = u < 0.5f ? step : std::nextafter(step, 1.0f); break;
          case 4: v = u < 0.7f ? 0.0f : step * (0.5f + u); break;
          case 5: v = 1e-5f * std::pow(8000.0f, u); break;
          default:
          {
            // low bits all ones, all zeros or near either: keys on the edges of the digits' buckets
            const std::uint32_t low[] = {0u, 1u, 0x7FFFu, 0x8000u, 0xFFFEu, 0xFFFFu};
            const std::uint32_t key = (bitsOf(step * (0.5f + u)) & ~0xFFFFu) | low[rng() % 6];
            std::memcpy(&v, &key, sizeof v);
          }
        }
      }
      std::vector<float> work = d;  // (overwritten on the selection over all)
      const float want = referenceMedian(d, -1.0f);
      EXPECT_EQ(bitsOf(median(work.data(), total, -1.0f)), bitsOf(want)) << total << " kind " << kind;
      EXPECT_EQ(median.bracketed(), total >= 8192 && kind != 4) << total << " kind " << kind;
    }
}

TEST(GridResolution, MeasuredResolutionAtTheEdgesOfTheBracket)
{
  // 10240 spacings: the sample is every tenth, so its counts of each value fix the bracket (the
  // values of sample ranks 448 and 576 of 1024). Four values Z < A < B < C, one float step
  // apart (an edge taken one step or one rank off changes the answer or the path) or 10 % apart
  // (a bracket wider than one digit, its edges at the ends of the digits' ranges).
  enum { Z, A, B, C };
  struct Case
  {
    const char* what;
    std::vector<std::pair<int, int>> sampled, all;  // (value, count) in the sample and in all
    int want;
    bool bracketed;
  };
  const std::vector<Case> cases = {
      // lo = B holds the median; 5000 below it
      {"median on lo", {{A, 448}, {B, 53}, {C, 523}}, {{A, 5000}, {B, 300}, {C, 4940}}, B, true},
      // hi = B holds the median
      {"median on hi", {{Z, 100}, {A, 400}, {B, 200}, {C, 324}}, {{Z, 1000}, {A, 4000}, {B, 300}, {C, 4940}}, B, true},
      // the first value above hi: rank n / 2 = below + inside, a miss
      {"just above hi", {{Z, 100}, {A, 400}, {B, 150}, {C, 374}}, {{Z, 1000}, {A, 3000}, {B, 1120}, {C, 5120}}, C, false},
      // lo = hi = A, the median the last value below it: a miss
      {"just below lo", {{Z, 400}, {A, 200}, {B, 424}}, {{Z, 5121}, {A, 2000}, {B, 3119}}, Z, false},
      // lo = hi = A holds it
      {"lo equals hi", {{Z, 100}, {A, 900}, {B, 24}}, {{Z, 1000}, {A, 8000}, {B, 1240}}, A, true},
  };
  std::mt19937 rng(3);
  SpacingMedian median;
  const float a = 0.2f * kDegF;
  for (bool wide : {false, true})
  {
    const float value[] = {wide ? 0.9f * a : std::nextafter(a, 0.0f), a, wide ? 1.1f * a : std::nextafter(a, 1.0f),
                           wide ? 1.2f * a : std::nextafter(std::nextafter(a, 1.0f), 1.0f)};
    for (const Case& k : cases)
    {
      std::vector<float> sampled, others;
      for (const auto& [v, count] : k.sampled) sampled.insert(sampled.end(), static_cast<std::size_t>(count), value[v]);
      for (const auto& [v, count] : k.all)
      {
        const auto in_sample = std::count(sampled.begin(), sampled.end(), value[v]);
        others.insert(others.end(), static_cast<std::size_t>(count - in_sample), value[v]);
      }
      ASSERT_EQ(sampled.size(), 1024u) << k.what;
      ASSERT_EQ(others.size(), 9216u) << k.what;
      std::shuffle(sampled.begin(), sampled.end(), rng);
      std::shuffle(others.begin(), others.end(), rng);
      std::vector<float> d(10240);
      for (std::size_t i = 0, o = 0; i < d.size(); ++i) d[i] = i % 10 == 0 ? sampled[i / 10] : others[o++];
      const float want = value[k.want];
      ASSERT_EQ(bitsOf(referenceMedian(d, -1.0f)), bitsOf(want)) << k.what;  // the case is what it says
      EXPECT_EQ(bitsOf(median(d.data(), d.size(), -1.0f)), bitsOf(want)) << k.what << " wide " << wide;
      EXPECT_EQ(median.bracketed(), k.bracketed) << k.what << " wide " << wide;
    }
  }
}

TEST(GridResolution, MeasuredResolutionIsTheMedianOfTheGridsSpacings)
{
  // The whole path: a 16-ring frame of 0.2 deg steps (28.8k samples, past the sample's
  // threshold), the reference formed from the grid's own azimuths ring by ring.
  const ScannedFrame f = roomOnGround();
  Pipeline p;
  FrameResult r;
  ASSERT_TRUE(p.process(f.cloud.view(), r).ok);
  const ScanGrid& g = p.grid();
  ASSERT_EQ(g.num_duplicates + g.num_second_returns, 0u);  // the grid's azimuths are the ones measured
  std::vector<float> d;
  for (int n = 0; n < g.num_rings; ++n)
    for (std::uint32_t q = g.ring_begin[static_cast<std::size_t>(n)] + 1; q < g.ring_begin[static_cast<std::size_t>(n) + 1]; ++q)
    {
      float s = g.azimuth[q] - g.azimuth[q - 1];
      if (s >= kPiF) s -= kTwoPiF;
      if (s < -kPiF) s += kTwoPiF;
      d.push_back(std::fabs(s));
    }
  EXPECT_GT(d.size(), 8192u);
  EXPECT_EQ(bitsOf(g.azimuth_resolution), bitsOf(referenceMedian(d, -1.0f)));
}
