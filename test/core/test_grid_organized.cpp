// Organized clouds: the float32 input pass and placement against the generic input pass and
// placement of float64 records, and the ring field check on the float32 path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "../support/same_bits.hpp"
#include "../support/synthetic_cloud.hpp"
#include "ring_curvature/pipeline.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
// An organized frame of `rows` x `cols`, ring 0 at the top, with NaN padding, returns below the
// minimum range and signed zeros, written as float32 records and as the same values in float64
// records (which take the generic input pass and placement). Row 5 is all padding, row 7 all
// valid (whole groups of 8 and 16 kept).
struct Frame
{
  SyntheticCloud f32{false}, f64{true};
};
Frame organizedFrame(int rows, std::size_t cols, unsigned seed)
{
  Frame f;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int row = 0; row < rows; ++row)
    for (std::size_t c = 0; c < cols; ++c)
    {
      const int ring = rows - 1 - row;
      const std::size_t k = static_cast<std::size_t>(row) * cols + c;
      if ((k % 7 == 3 && row != 7) || (row == 2 && c < 20) || row == 5)  // padding, scattered, in runs
      {
        f.f32.addNaN(ring);
        f.f64.addNaN(ring);
        continue;
      }
      const double az = 2 * 3.14159265358979 * static_cast<double>(c) / static_cast<double>(cols);
      const double el = -0.3 + 0.6 * ring / rows;
      // 0.05: below min_range
      const double r = k % 11 == 5 && row != 7 ? 0.05 : 4.0 + 2.0 * std::sin(3 * az) + 0.01 * u(rng);
      auto x = static_cast<float>(r * std::cos(el) * std::cos(az));
      auto y = static_cast<float>(r * std::cos(el) * std::sin(az));
      const auto z = static_cast<float>(r * std::sin(el));
      if (k % 13 == 0) y = -0.0f;  // on the axis
      if (k % 17 == 0) x = 0.0f;
      f.f32.add(x, y, z, ring);
      f.f64.add(x, y, z, ring);  // float values, exactly
    }
  return f;
}
}  // namespace

// The float32 path must give the grid the generic path gives, bit for bit: every per-position
// and per-point array, the ring bounds and elevations, the measured resolution and the labels.
// Widths that are and are not multiples of sixteen and eight (the vectorized loops' groups),
// and one under eight.
TEST(OrganizedGrid, Float32PathMatchesTheGenericPath)
{
  for (const int width : {256, 203, 40, 24, 17, 5})
  {
    const auto cols = static_cast<std::size_t>(width);
    const Frame f = organizedFrame(16, cols, static_cast<unsigned>(cols));
    Pipeline fast, generic;
    FrameResult rf, rg;
    ASSERT_TRUE(fast.process(f.f32.view(16), rf).ok);
    ASSERT_TRUE(generic.process(f.f64.view(16), rg).ok);
    const ScanGrid &a = fast.grid(), &b = generic.grid();
    ASSERT_TRUE(a.organized);
    EXPECT_GT(a.size(), 8 * cols);
    EXPECT_LT(a.size(), 16 * cols);
    EXPECT_EQ(a.num_rings, b.num_rings);
    EXPECT_EQ(a.num_input, b.num_input);
    EXPECT_EQ(a.num_valid, b.num_valid);
    EXPECT_TRUE(sameBits(a.ring_begin, b.ring_begin)) << cols;
    EXPECT_TRUE(sameBits(a.ring_elevation, b.ring_elevation)) << cols;
    EXPECT_TRUE(sameBits(a.ring_cos, b.ring_cos)) << cols;
    EXPECT_EQ(a.azimuth_resolution, b.azimuth_resolution);
    EXPECT_TRUE(sameBits(a.index, b.index)) << cols;
    EXPECT_TRUE(sameBits(a.azimuth, b.azimuth)) << cols;
    EXPECT_TRUE(sameBits(a.x, b.x)) << cols;
    EXPECT_TRUE(sameBits(a.y, b.y)) << cols;
    EXPECT_TRUE(sameBits(a.z, b.z)) << cols;
    EXPECT_TRUE(sameBits(a.range, b.range)) << cols;
    EXPECT_TRUE(sameBits(a.linked, b.linked)) << cols;
    EXPECT_TRUE(sameBits(a.up, b.up)) << cols;
    EXPECT_TRUE(sameBits(a.state, b.state)) << cols;
    EXPECT_TRUE(sameBits(a.grid_pos, b.grid_pos)) << cols;
    EXPECT_TRUE(sameBits(rf.label, rg.label)) << cols;
    EXPECT_TRUE(sameBits(rf.curvature, rg.curvature)) << cols;
  }
}

// A ring field at or beyond max_rings is an error naming the first such point, wherever it is
// (inside a row, or the last point); the grid is left empty and the next good frame is
// processed normally.
TEST(OrganizedGrid, RingFieldOutOfRangeNamesThePoint)
{
  Params params;
  params.max_rings = 16;
  for (const std::size_t bad : {std::size_t{37}, std::size_t{16 * 64 - 1}})
  {
    Frame f = organizedFrame(16, 64, 3);
    const std::uint16_t ring = 40;
    std::memcpy(f.f32.bytes().data() + bad * f.f32.pointStep() + 16, &ring, sizeof ring);
    Pipeline p(params);
    FrameResult r;
    const Status st = p.process(f.f32.view(16), r);
    ASSERT_FALSE(st.ok);
    EXPECT_NE(st.message.find("point " + std::to_string(bad) + " has ring 40"), std::string::npos) << st.message;
    EXPECT_EQ(p.grid().size(), 0u);
    EXPECT_EQ(p.grid().x.size(), 0u);
    EXPECT_EQ(p.grid().num_rings, 0);
    const Frame good = organizedFrame(16, 64, 4);
    ASSERT_TRUE(p.process(good.f32.view(16), r).ok);
    EXPECT_EQ(r.label.size(), 16u * 64u);
    EXPECT_GT(p.grid().size(), 8u * 64u);
  }
}

// An organized row's links go by columns: a sample links to the one before it in its row when
// at most max_gap_samples columns between them are missing, and the row closes across the seam
// on the same rule; the azimuth resolution is the spacing per column, whatever the gaps. Gaps
// of one to four columns inside rows and at their ends, on both input paths (float32 and the
// generic float64 one).
TEST(OrganizedGrid, LinksGoByColumnsAcrossGaps)
{
  const int rows = 8;
  const std::size_t W = 256;
  Params params;
  ASSERT_EQ(params.max_gap_samples, 2);
  const auto missing = [](int row, std::size_t c) {
    if (row == 1) return c == 10 || c == 20 || c == 21 || (c >= 30 && c < 33) || (c >= 40 && c < 44);
    if (row == 2) return c < 2;                // the seam: 2 + 256 - 255 = 3 columns apart, closed
    if (row == 3) return c < 3;                // 4 apart: open
    if (row == 4) return c >= 253;             // 0 + 256 - 252 = 4 apart: open
    if (row == 5) return (c * 7) % 11 == 3;    // scattered single gaps
    return false;
  };
  SyntheticCloud f32{false}, f64{true};
  for (int row = 0; row < rows; ++row)
    for (std::size_t c = 0; c < W; ++c)
    {
      const int ring = rows - 1 - row;
      if (missing(row, c))
      {
        f32.addNaN(ring);
        f64.addNaN(ring);
        continue;
      }
      // clockwise, as the sensors sweep, a column's azimuth whatever the gaps
      const double az = 3.0 - 2 * 3.14159265358979 * static_cast<double>(c) / static_cast<double>(W);
      const double el = -0.2 + 0.05 * ring, r = 5.0 + 0.5 * std::sin(4 * az);
      const double x = r * std::cos(el) * std::cos(az), y = r * std::cos(el) * std::sin(az), z = r * std::sin(el);
      f32.add(x, y, z, ring);
      f64.add(x, y, z, ring);
    }
  for (const SyntheticCloud* cloud : {&f32, &f64})
  {
    Pipeline p(params);
    FrameResult res;
    ASSERT_TRUE(p.process(cloud->view(rows), res).ok);
    const ScanGrid& g = p.grid();
    ASSERT_TRUE(g.organized);
    ASSERT_EQ(g.num_rings, rows);
    EXPECT_NEAR(g.azimuth_resolution, 2 * 3.14159265358979 / W, 1e-5);
    const auto max_cols = static_cast<std::size_t>(params.max_gap_samples) + 1;
    std::size_t unlinked = 0;
    for (int n = 0; n < rows; ++n)
    {
      const auto ring = static_cast<std::size_t>(n);
      const std::uint32_t b = g.ring_begin[ring], e = g.ring_begin[ring + 1];
      ASSERT_GT(e - b, 3u);
      for (std::uint32_t q = b + 1; q < e; ++q)
      {
        const std::size_t c0 = g.index[q - 1] % W, c1 = g.index[q] % W;
        ASSERT_EQ(g.index[q] / W, static_cast<std::size_t>(n));
        EXPECT_EQ(g.linked[q] != 0, c1 - c0 <= max_cols) << "row " << n << " column " << c1;
        unlinked += g.linked[q] == 0 ? 1 : 0;
      }
      const std::size_t first = g.index[b] % W, last = g.index[e - 1] % W;
      const bool closed = first + W - last <= max_cols;
      EXPECT_EQ(g.ring_closed[ring] != 0, closed) << "row " << n;
      EXPECT_EQ(g.linked[b] != 0, closed) << "row " << n;
    }
    EXPECT_EQ(unlinked, 2u);  // row 1's gaps of three and four columns
    EXPECT_TRUE(g.ring_closed[2] && !g.ring_closed[3] && !g.ring_closed[4] && g.ring_closed[5]);
  }
}

// Every other column missing in every row (a sensor's low-bandwidth mode, or a decimating
// driver): the resolution is still the spacing of one column, and every sample links to the one
// two columns before it.
TEST(OrganizedGrid, ResolutionIsPerColumnWithEveryOtherColumnMissing)
{
  const int rows = 4;
  const std::size_t W = 128;
  for (const bool float64 : {false, true})
  {
    SyntheticCloud cloud{float64};
    for (int row = 0; row < rows; ++row)
      for (std::size_t c = 0; c < W; ++c)
      {
        if (c % 2 == 1)
        {
          cloud.addNaN(rows - 1 - row);
          continue;
        }
        const double az = 3.0 - 2 * 3.14159265358979 * static_cast<double>(c) / static_cast<double>(W);
        cloud.add(6.0 * std::cos(az), 6.0 * std::sin(az), -0.5 + 0.2 * row, rows - 1 - row);
      }
    Pipeline p;
    FrameResult res;
    ASSERT_TRUE(p.process(cloud.view(rows), res).ok);
    const ScanGrid& g = p.grid();
    EXPECT_NEAR(g.azimuth_resolution, 2 * 3.14159265358979 / W, 1e-5) << (float64 ? "float64" : "float32");
    for (int n = 0; n < rows; ++n)
    {
      const auto ring = static_cast<std::size_t>(n);
      const std::uint32_t b = g.ring_begin[ring], e = g.ring_begin[ring + 1];
      ASSERT_EQ(e - b, W / 2);
      for (std::uint32_t q = b + 1; q < e; ++q) EXPECT_EQ(g.linked[q], 1u) << "row " << n << " position " << q;
    }
  }
}
