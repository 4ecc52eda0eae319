// The sort keys of rings that come one after another (KITTI's layout), and their insertion sort:
// each ring's order must be exactly (azimuth, input index), whatever the run lengths, the
// invalid points between them, -0 azimuths and ties.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "../support/synthetic_cloud.hpp"
#include "common/float_bits.hpp"
#include "ring_curvature/pipeline.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

TEST(RingKeys, ConsecutiveRingsAreOrderedByAzimuthThenIndex)
{
  // Ring after ring, clockwise (decreasing azimuth) or not, with local disorder; ring lengths
  // that are not multiples of eight, invalid points here and there (they break the runs),
  // a few rings of one to five points, repeated azimuths (ties broken by the input index) and
  // points on the +x axis with y = -0 (azimuth -0, which must sort and read as +0).
  // duplicate_azimuth_fraction = 0: nothing is folded or removed, every valid point is on the
  // grid, so the grid's rings are the sort's output.
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> jitter(-0.004f, 0.004f), range(3.0f, 40.0f);
  SyntheticCloud c;
  struct In
  {
    float x, y, z;
    int ring;
    bool valid;
  };
  std::vector<In> in;
  const int rings = 24;
  for (int r = 0; r < rings; ++r)
  {
    const int count = r % 6 == 5 ? 1 + r % 5 : 1500 + 37 * r;
    for (int k = 0; k < count; ++k)
    {
      const bool invalid = (k * 7 + r) % 97 == 3;
      const bool on_axis = k % 211 == 10;
      const bool tie = k % 53 == 20 && k > 0 && in.back().valid;
      const float turn = 6.2f * static_cast<float>(k) / static_cast<float>(count) + jitter(rng);
      const float az = r % 2 == 0 ? 3.1f - turn : turn - 3.1f;
      const float d = range(rng);
      float x = d * std::cos(az), y = d * std::sin(az);
      if (tie)
      {
        x = in.back().x * 1.5f;  // the previous point's azimuth, further out
        y = in.back().y * 1.5f;
      }
      if (on_axis)
      {
        x = d;
        y = -0.0f;
      }
      const float z = 0.1f * static_cast<float>(r) - 1.0f;
      if (invalid)
      {
        c.addNaN(r);
        in.push_back({std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f, r, false});
      }
      else
      {
        c.add(x, y, z, r);
        in.push_back({x, y, z, r, true});
      }
    }
  }
  Params params;
  params.duplicate_azimuth_fraction = 0.0f;
  Pipeline p(params);
  FrameResult res;
  ASSERT_TRUE(p.process(c.view(), res).ok);
  const ScanGrid& g = p.grid();
  ASSERT_EQ(g.num_rings, rings);
  std::size_t valid = 0;
  for (const In& q : in) valid += q.valid ? 1 : 0;
  ASSERT_EQ(g.num_valid, valid);
  const auto key = [&](std::uint32_t i) {
    return std::make_pair(detail::orderedKey(fastAtan2(in[i].y, in[i].x) + 0.0f), i);
  };
  std::size_t mismatches = 0;
  for (int r = 0; r < rings; ++r)
  {
    std::vector<std::uint32_t> want;
    for (std::uint32_t i = 0; i < in.size(); ++i)
      if (in[i].valid && in[i].ring == r) want.push_back(i);
    std::sort(want.begin(), want.end(), [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
    const auto ring = static_cast<std::size_t>(r);
    const std::uint32_t b = g.ring_begin[ring], e = g.ring_begin[ring + 1];
    ASSERT_EQ(e - b, want.size()) << "ring " << r;
    for (std::uint32_t q = 0; q < want.size(); ++q)
    {
      const std::uint32_t i = want[q];
      const float az = fastAtan2(in[i].y, in[i].x) + 0.0f;
      const bool same = g.index[b + q] == i && std::memcmp(&g.azimuth[b + q], &az, sizeof az) == 0 &&
                        g.state[i] == PointState::OnGrid && g.grid_pos[i] == static_cast<std::int32_t>(b + q);
      mismatches += same ? 0 : 1;
    }
  }
  EXPECT_EQ(mismatches, 0u);
}
