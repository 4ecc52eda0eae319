// Scan grid: seam, gaps, ring counts, empty frames, shuffled and organized input, bad views and
// the input pass's azimuths and ranges (dual returns: test_scan_grid_dual_returns.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>

#include "common/float_bits.hpp"
#include "ring_curvature/pipeline.hpp"
#include "scan_grid_rooms.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
constexpr double kDeg = 3.14159265358979323846 / 180;

std::size_t count(const FrameResult& r, Label l)
{
  return static_cast<std::size_t>(std::count(r.label.begin(), r.label.end(), static_cast<std::uint8_t>(l)));
}
}  // namespace

TEST(ScanGrid, EmptyFrameIsFine)
{
  SyntheticCloud c;
  Pipeline p;
  FrameResult r;
  const Status st = p.process(c.view(), r);
  EXPECT_TRUE(st.ok) << st.message;
  EXPECT_TRUE(r.label.empty());
  EXPECT_TRUE(r.primitives.primitives.empty());
}

TEST(ScanGrid, RingCounts16To128)
{
  for (int beams : {1, 16, 32, 64, 128})
  {
    const SensorModel s = SensorModel::uniform(beams, -10, 10, 0.4);
    const ScannedFrame f = scan(room(), s);
    Pipeline p;
    FrameResult r;
    ASSERT_TRUE(p.process(f.cloud.view(), r).ok) << beams;
    EXPECT_EQ(p.grid().num_rings, beams);
    EXPECT_EQ(p.grid().size(), f.cloud.size());  // every return on the grid
    for (int n = 0; n < beams; ++n) EXPECT_TRUE(p.grid().ring_closed[static_cast<std::size_t>(n)]) << beams << " ring " << n;
    // 4 corners per ring, each an Edge (peak only), all else Plane
    EXPECT_EQ(count(r, Label::Edge), static_cast<std::size_t>(4 * beams)) << beams << " beams";
    EXPECT_EQ(count(r, Label::Plane), f.cloud.size() - 4 * static_cast<std::size_t>(beams)) << beams;
    EXPECT_NEAR(p.grid().azimuth_resolution, 0.4 * kDeg, 1e-5);
    if (beams > 1)
    {
      // walls join across rings into 4 planar patches (a patch may not cross a corner)
      std::size_t planes = 0;
      for (const auto& pr : r.primitives.primitives) planes += pr.label == Label::Plane ? 1 : 0;
      EXPECT_EQ(planes, 4u) << beams;
    }
  }
}

TEST(ScanGrid, FeatureAcrossTheSeamIsFoundOnce)
{
  // Rotate the room so that one corner sits exactly on the 0/360 deg seam (azimuth 180 deg),
  // and start the sweep there: the corner's samples are split between the two ends of the ring.
  RayScene s = room();
  for (auto& b : s.boxes)
  {
    const double c = std::cos(-45 * kDeg), sn = std::sin(-45 * kDeg);
    const double x = b.cx, y = b.cy;
    b.cx = c * x - sn * y;
    b.cy = sn * x + c * y;
    b.yaw = -45 * kDeg;
  }
  const SensorModel m = SensorModel::uniform(4, -5, 5, 0.25);
  const ScannedFrame f = scan(s, m, 0.0, 1, 3.14159265358979323846);  // sweep starts at the seam
  Pipeline p;
  FrameResult r;
  ASSERT_TRUE(p.process(f.cloud.view(), r).ok);
  EXPECT_EQ(count(r, Label::Edge), 16u);  // 4 corners x 4 rings, the seam corner not doubled nor lost
  std::size_t planes = 0;
  for (const auto& pr : r.primitives.primitives) planes += pr.label == Label::Plane ? 1 : 0;
  EXPECT_EQ(planes, 4u);  // the wall split by the seam is one patch
}

TEST(ScanGrid, NaNGapsBreakTheCurve)
{
  const SensorModel m = SensorModel::uniform(1, 0, 0, 0.4);
  ScannedFrame f = scan(room(), m);
  // punch a 10-sample hole in the middle of a wall (azimuth 0 is the middle of the +x wall)
  SyntheticCloud holed;
  const std::size_t n = f.cloud.size();
  std::vector<std::size_t> gone;
  for (std::size_t i = 0; i < n; ++i)
  {
    const auto* rec = f.cloud.bytes().data() + i * f.cloud.pointStep();
    float x, y, z;
    std::memcpy(&x, rec, 4);
    std::memcpy(&y, rec + 4, 4);
    std::memcpy(&z, rec + 8, 4);
    if (i >= 100 && i < 110)
    {
      holed.addNaN(0);
      gone.push_back(i);
    }
    else
      holed.add(x, y, z, 0);
  }
  Pipeline p;
  FrameResult r;
  ASSERT_TRUE(p.process(holed.view(), r).ok);
  for (std::size_t i : gone)
  {
    EXPECT_EQ(r.label[i], 0) << i;
    EXPECT_TRUE(std::isnan(r.curvature[i]));
  }
  // no curvature invented across the hole: the samples beside it have a one-sided neighbourhood
  EXPECT_TRUE(std::isnan(r.curvature[99]));
  EXPECT_TRUE(std::isnan(r.curvature[110]));
  EXPECT_EQ(r.label[99], static_cast<std::uint8_t>(Label::Plane));
  EXPECT_EQ(count(r, Label::Edge), 4u);
  EXPECT_EQ(p.grid().num_valid + 10, n);
}

TEST(ScanGrid, AnyInputOrderGivesTheSameLabels)
{
  // Drivers emit rings in firing order: counter-clockwise or clockwise, starting anywhere. The
  // grid takes a presorted ring as it is (reversed or rotated to the seam when needed) and sorts
  // the others; every ordering, down to a full shuffle, must give the same labels per point.
  const ScannedFrame f = roomOnGround();
  Pipeline p;
  FrameResult ref;
  ASSERT_TRUE(p.process(f.cloud.view(), ref).ok);
  const std::size_t n = f.cloud.size(), per_ring = n / 16;
  auto reorder = [&](auto index_of) {  // point i of the new cloud is point index_of(i) of f
    SyntheticCloud c;
    c.bytes().resize(f.cloud.bytes().size());
    std::vector<std::size_t> from(n);
    for (std::size_t i = 0; i < n; ++i)
    {
      from[i] = index_of(i);
      std::memcpy(c.bytes().data() + i * 22, f.cloud.bytes().data() + from[i] * 22, 22);
    }
    FrameResult r;
    EXPECT_TRUE(p.process(c.view(), r).ok);
    std::size_t same = 0;
    for (std::size_t i = 0; i < n; ++i) same += r.label[i] == ref.label[from[i]] ? 1 : 0;
    return same;
  };
  // every ring reversed (a clockwise sensor)
  EXPECT_EQ(reorder([&](std::size_t i) { return n - 1 - i; }), n);
  // every ring starting a third of the way round (not at the seam)
  EXPECT_EQ(reorder([&](std::size_t i) {
              const std::size_t ring = i / per_ring, k = i % per_ring;
              return ring * per_ring + (k + per_ring / 3) % per_ring;
            }),
            n);
  // reversed and rotated
  EXPECT_EQ(reorder([&](std::size_t i) {
              const std::size_t ring = i / per_ring, k = per_ring - 1 - i % per_ring;
              return ring * per_ring + (k + 2 * per_ring / 5) % per_ring;
            }),
            n);
  // a few neighbours swapped (not monotonic: the sort's fallback)
  EXPECT_EQ(reorder([&](std::size_t i) { return i % 97 == 5 ? i + 1 : (i % 97 == 6 ? i - 1 : i); }), n);
  // every point anywhere (rings interleaved, no order at all)
  std::vector<std::size_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(5));
  EXPECT_EQ(reorder([&](std::size_t i) { return perm[i]; }), n);
}

TEST(ScanGrid, RingsFromElevationMatchTheRingField)
{
  // A cloud without `ring` (opt-in ring_from_elevation): beams are found by clustering elevation
  // angles, numbered from the lowest up like velodyne_pointcloud, so the result must equal the
  // one computed with the driver's ring field.
  const ScannedFrame f = roomOnGround();
  Pipeline with_field;
  FrameResult ref;
  ASSERT_TRUE(with_field.process(f.cloud.view(), ref).ok);

  PointCloudView v = f.cloud.view();
  v.ring = {};
  Pipeline refuses;
  FrameResult r;
  EXPECT_FALSE(refuses.process(v, r).ok);  // not without opting in
  Params opt_in;
  opt_in.ring_from_elevation = true;
  Pipeline derived(opt_in);
  ASSERT_TRUE(derived.process(v, r).ok);
  EXPECT_EQ(derived.grid().num_rings, 16);
  EXPECT_EQ(r.label, ref.label);
  EXPECT_EQ(r.primitive, ref.primitive);
}

TEST(ScanGrid, OrganizedCloudUsesRowsAndColumns)
{
  // Ouster-like: rows are beams, ring 0 at the top, NaN where there is no return.
  const SensorModel m = SensorModel::uniform(8, -10, 10, 360.0 / 512);
  RayScene s = room();
  const ScannedFrame f = scan(s, m);
  // reverse row order (ring 0 = highest) and drop a few returns (at other columns on each row)
  SyntheticCloud org;
  const std::size_t cols = f.cloud.size() / 8;
  for (int row = 7; row >= 0; --row)
    for (std::size_t c = 0; c < cols; ++c)
    {
      const std::size_t i = static_cast<std::size_t>(row) * cols + c;
      if (c % 50 == static_cast<std::size_t>(7 + 3 * row))
      {
        org.addNaN(7 - row);
        continue;
      }
      float x, y, z;
      std::memcpy(&x, f.cloud.bytes().data() + i * 22, 4);
      std::memcpy(&y, f.cloud.bytes().data() + i * 22 + 4, 4);
      std::memcpy(&z, f.cloud.bytes().data() + i * 22 + 8, 4);
      org.add(x, y, z, 7 - row);
    }
  Pipeline p;
  FrameResult r;
  ASSERT_TRUE(p.process(org.view(8), r).ok);
  EXPECT_TRUE(p.grid().organized);
  EXPECT_EQ(p.grid().num_rings, 8);
  EXPECT_EQ(count(r, Label::Edge), 32u);
  // the vertical neighbour is the same column one row up, none where that return is missing
  const ScanGrid& g = p.grid();
  std::size_t missing_above = 0;
  for (std::size_t pos = 0; pos < g.size(); ++pos)
  {
    const std::size_t i = g.index[pos], above = i + cols;
    const bool on_grid = above < g.num_input && g.state[above] == PointState::OnGrid;
    missing_above += above < g.num_input && !on_grid ? 1 : 0;
    EXPECT_EQ(g.up[pos], on_grid ? g.grid_pos[above] : -1) << pos;
  }
  EXPECT_GT(missing_above, 20u);
  std::size_t planes = 0;
  for (const auto& pr : r.primitives.primitives) planes += pr.label == Label::Plane ? 1 : 0;
  EXPECT_EQ(planes, 4u);
}

TEST(ScanGrid, RejectsBadViewsWithAClearMessage)
{
  SyntheticCloud c;
  c.add(1, 2, 3, 0);
  c.add(1, 2, 3.1, 0);
  Pipeline p;
  FrameResult r;
  PointCloudView v = c.view();
  v.ring = {};
  Status st = p.process(v, r);
  EXPECT_FALSE(st.ok);
  EXPECT_NE(st.message.find("ring"), std::string::npos) << st.message;
  v = c.view();
  v.ring.type = ScalarType::Float32;
  st = p.process(v, r);
  EXPECT_NE(st.message.find("integer"), std::string::npos) << st.message;
  v = c.view();
  v.data_size -= 1;
  st = p.process(v, r);
  EXPECT_NE(st.message.find("truncated"), std::string::npos) << st.message;
  v = c.view();
  v.x.offset = 20;
  st = p.process(v, r);
  EXPECT_NE(st.message.find("outside the point record"), std::string::npos) << st.message;
  v = c.view();
  v.y.offset = 2;
  st = p.process(v, r);
  EXPECT_NE(st.message.find("overlap"), std::string::npos) << st.message;
  Params small;
  small.max_rings = 1;
  Pipeline q(small);
  c.add(1, 2, 3.2, 5);
  st = q.process(c.view(), r);
  EXPECT_NE(st.message.find("max_rings"), std::string::npos) << st.message;
  // and the next good frame is processed normally
  SyntheticCloud good;
  good.add(1, 2, 3, 0);
  good.add(1, 2.1, 3, 0);
  good.add(1, 2.2, 3, 0);
  EXPECT_TRUE(q.process(good.view(), r).ok);
  EXPECT_EQ(r.label.size(), 3u);
}

// The input pass's vectorized loops (their clones included): every point on the grid must carry
// exactly fastAtan2(y, x) of its float coordinates and the double range sqrt((x x + y y) + z z), special
// values included (signed zeros, subnormals, |x| = |y|, the axes), and points out of range or NaN
// must stay off the grid.
TEST(ScanGrid, InputPassGivesExactAzimuthsAndRanges)
{
  const float specials[] = {0.0f, -0.0f, 1e-40f, -1e-40f, 1.0f, -1.0f, 2.5f, -2.5f, 1e3f, -1e3f, 7.0e-3f, -3.0f};
  SyntheticCloud c;
  std::vector<float> xs, ys, zs;
  int ring = 0;
  const auto add = [&](float x, float y, float z) {
    c.add(x, y, z, ring);
    xs.push_back(x);
    ys.push_back(y);
    zs.push_back(z);
    ring = (ring + 1) % 16;
  };
  for (float x : specials)
    for (float y : specials) add(x, y, 4.0f);
  add(std::numeric_limits<float>::quiet_NaN(), 1.0f, 1.0f);
  add(0.01f, 0.0f, 0.0f);  // below min_range
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-50.0f, 50.0f);
  for (int k = 0; k < 20003; ++k) add(u(rng), u(rng), u(rng) * 0.1f);  // not a multiple of 8
  Pipeline p;
  FrameResult r;
  ASSERT_TRUE(p.process(c.view(), r).ok);
  const ScanGrid& g = p.grid();
  std::size_t on_grid = 0;
  for (std::size_t i = 0; i < xs.size(); ++i)
  {
    const double x = xs[i], y = ys[i], z = zs[i];
    const double range = std::sqrt(x * x + y * y + z * z);
    if (!(range >= p.params().min_range && range <= p.params().max_range))
    {
      EXPECT_EQ(g.state[i], PointState::Invalid) << i;
      continue;
    }
    if (g.state[i] != PointState::OnGrid) continue;  // a duplicate of the same azimuth and range
    ++on_grid;
    const auto pos = static_cast<std::size_t>(g.grid_pos[i]);
    ASSERT_EQ(g.index[pos], i);
    const float az = fastAtan2(ys[i], xs[i]);
    EXPECT_EQ(std::memcmp(&g.azimuth[pos], &az, sizeof az), 0) << i << ": " << g.azimuth[pos] << " vs " << az;
    EXPECT_EQ(std::memcmp(&g.range[pos], &range, sizeof range), 0) << i;
    EXPECT_EQ(g.x[pos], x);
    EXPECT_EQ(g.z[pos], z);
  }
  // (random azimuths: some points fall within one firing of another and leave the grid as
  // second returns; most stay)
  EXPECT_GT(on_grid, xs.size() / 2);
}
