// The output stage: every input point's label, features and primitive are its grid position's,
// bit for bit, and the points off the grid get none. The stage selects point by point between the
// two, so the first frame mixes every state among neighbours and has stretches with every point
// off the grid and with all on it; the second comes ring by ring, with gaps, duplicates and
// second returns.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "../support/ray_scene.hpp"
#include "ring_curvature/pipeline.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
// A room on level ground, as a dual-return driver emits it: each firing's first return, then a
// second one that is mostly an identical copy (Duplicate), sometimes 0.3 m further (SecondReturn),
// with no-returns (Invalid) where the beams miss and a few more cut out, and stretches where
// neither return came back.
SyntheticCloud dualReturnRoom()
{
  const ScannedFrame f = scan(squareRoom(-1.8), SensorModel::uniform(16, -15, 15, 0.4), 0.005, 5);
  SyntheticCloud c;
  for (std::size_t i = 0; i < f.cloud.size(); ++i)
  {
    float xyz[3];
    std::memcpy(xyz, f.cloud.bytes().data() + i * 22, sizeof xyz);
    const int ring = f.ring[i];
    if (i % 29 == 7)
    {
      c.addNaN(ring);
      continue;
    }
    if (i % 211 >= 100 && i % 211 < 112)  // both returns missing, twelve firings in a row
    {
      c.addNaN(ring);
      c.addNaN(ring);
      continue;
    }
    c.add(xyz[0], xyz[1], xyz[2], ring);
    if (i % 5 == 3) continue;  // a single return
    const double r = std::sqrt(double(xyz[0]) * xyz[0] + double(xyz[1]) * xyz[1] + double(xyz[2]) * xyz[2]);
    const double k = i % 7 == 2 ? (r + 0.3) / r : 1.0;
    c.add(xyz[0] * k, xyz[1] * k, xyz[2] * k, ring);
  }
  for (int k = 0; c.size() % 16 != 1; ++k) c.add(1.0 + 0.01 * k, 2.0, 0.1, 3);  // off a multiple of sixteen and eight
  return c;
}

// The room as a driver that sends its rings one after another emits it (KITTI's order): each
// ring's points in the order scanned, with no-returns here and there and twelve in a row in
// places, now and then a second return that copies the first (Duplicate) or lies 0.3 m further
// (SecondReturn).
SyntheticCloud ringByRingRoom()
{
  const ScannedFrame f = scan(squareRoom(-1.8), SensorModel::uniform(16, -15, 15, 0.4), 0.005, 5);
  SyntheticCloud c;
  for (int ring = 0; ring < 16; ++ring)
    for (std::size_t i = 0; i < f.cloud.size(); ++i)
    {
      if (f.ring[i] != ring) continue;
      float xyz[3];
      std::memcpy(xyz, f.cloud.bytes().data() + i * 22, sizeof xyz);
      if (i % 31 == 7 || i % 499 < 12)
      {
        c.addNaN(ring);
        continue;
      }
      c.add(xyz[0], xyz[1], xyz[2], ring);
      if (i % 97 == 3) c.add(xyz[0], xyz[1], xyz[2], ring);
      if (i % 89 == 5)
      {
        const double r = std::sqrt(double(xyz[0]) * xyz[0] + double(xyz[1]) * xyz[1] + double(xyz[2]) * xyz[2]);
        const double k = (r + 0.3) / r;
        c.add(xyz[0] * k, xyz[1] * k, xyz[2] * k, ring);
      }
    }
  for (int k = 0; c.size() % 16 != 7; ++k) c.add(1.0 + 0.01 * k, 2.0, 0.1, 15);  // off a multiple of sixteen and eight
  return c;
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
}  // namespace

// Every point's outputs against its grid position's, twice (the second time into warm arrays).
void expectGridPositionsResults(const SyntheticCloud& c)
{
  Pipeline p;
  FrameResult r;
  for (int pass = 0; pass < 2; ++pass)  // the second time into warm arrays
  {
    ASSERT_TRUE(p.process(c.view(), r).ok);
    const ScanGrid& g = p.grid();
    const Features& f = p.features();
    const std::vector<Label>& lab = p.gridLabels();
    const std::size_t n = c.size();
    ASSERT_NE(n % 8, 0u);  // (a tail for the one-at-a-time loop)
    ASSERT_EQ(r.label.size(), n);
    ASSERT_EQ(g.state.size(), n);
    constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
    std::size_t wrong = 0, on_grid = 0, off_grid = 0;
    for (std::size_t i = 0; i < n; ++i)
    {
      bool ok;
      if (g.state[i] == PointState::OnGrid || g.state[i] == PointState::Duplicate)
      {
        const auto q = static_cast<std::size_t>(g.grid_pos[i]);
        ok = r.label[i] == static_cast<std::uint8_t>(lab[q]) && sameBits(r.curvature[i], f.curvature[q]) &&
             sameBits(r.smoothness[i], f.smoothness[q]) && sameBits(r.discontinuity[i], f.discontinuity[q]) &&
             r.primitive[i] == r.primitives.of_grid[q];
        ++on_grid;
      }
      else
      {
        ok = r.label[i] == static_cast<std::uint8_t>(Label::None) && sameBits(r.curvature[i], kNaN) &&
             sameBits(r.smoothness[i], kNaN) && sameBits(r.discontinuity[i], kNaN) && r.primitive[i] == -1;
        ++off_grid;
      }
      if (!ok && wrong++ < 5) ADD_FAILURE() << "point " << i << " state " << static_cast<int>(g.state[i]);
    }
    EXPECT_EQ(wrong, 0u);
    EXPECT_GT(off_grid, n / 20);
    // labels other than None and primitives are there to be gathered
    std::size_t labelled = 0, in_primitive = 0;
    for (std::size_t i = 0; i < n; ++i)
    {
      labelled += r.label[i] != static_cast<std::uint8_t>(Label::None) ? 1 : 0;
      in_primitive += r.primitive[i] >= 0 ? 1 : 0;
    }
    EXPECT_GT(labelled, on_grid / 2);
    EXPECT_GT(in_primitive, on_grid / 4);
  }
}

TEST(OutputGather, EveryPointGetsItsGridPositionsResultsBitForBit)
{
  const SyntheticCloud c = dualReturnRoom();
  Pipeline p;
  FrameResult r;
  ASSERT_TRUE(p.process(c.view(), r).ok);
  EXPECT_GT(p.grid().num_duplicates, c.size() / 4);
  EXPECT_GT(p.grid().num_second_returns, c.size() / 20);
  expectGridPositionsResults(c);
}

TEST(OutputGather, RingByRingFrameGetsItsGridPositionsResultsBitForBit)
{
  const SyntheticCloud c = ringByRingRoom();
  Pipeline p;
  FrameResult r;
  ASSERT_TRUE(p.process(c.view(), r).ok);
  const ScanGrid& g = p.grid();
  EXPECT_GT(g.num_duplicates, 0u);
  EXPECT_GT(g.num_second_returns, 0u);
  expectGridPositionsResults(c);
}
