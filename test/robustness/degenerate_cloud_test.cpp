// Degenerate but legal clouds through the core (PointCloudView + Pipeline::process): one point,
// all NaN, one ring, shuffled order, 2 million points, equivalent layouts and frames of changing
// sizes must be processed, with a consistent result and no crash or out-of-bounds read (the
// sanitizer build runs this file too), and leave a pipeline that processes the next good frame
// exactly as a fresh pipeline would (malformed clouds: malformed_cloud_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include "malformed_fixture.hpp"

namespace rc = ring_curvature;
using rc::test::Cloud;
using rc::test::expectConsistent;
using rc::test::expectSameResult;
using rc::test::Malformed;

namespace
{

// --- degenerate but legal frames --------------------------------------------------------------

void processLegal(const rc::PointCloudView& v, rc::FrameResult& r, const rc::Params& p = {})
{
  rc::Pipeline pipeline(p);
  const rc::Status st = pipeline.process(v, r);
  ASSERT_TRUE(st.ok) << st.message;
  expectConsistent(r, v.size());
}

TEST_F(Malformed, OnePoint)
{
  const Cloud c = rc::test::pack(rc::test::roomScan(1, 1), rc::test::velodyneLayout(), 1, 1);
  rc::FrameResult r;
  processLegal(c.view(), r);
  EXPECT_TRUE(std::isnan(r.curvature[0])) << "curvature of a lone point must be undefined";
  EXPECT_TRUE(r.primitives.primitives.empty());
}

TEST_F(Malformed, AllNaNOrInfinite)
{
  const float vals[] = {std::numeric_limits<float>::quiet_NaN(),
                        std::numeric_limits<float>::infinity(),
                        -std::numeric_limits<float>::infinity()};
  for (float bad : vals)
  {
    auto pts = rc::test::roomScan(16, 360);
    for (auto& p : pts)
      p.x = p.y = p.z = bad;
    const Cloud c = rc::test::pack(pts, rc::test::velodyneLayout(), 16 * 360, 1);
    rc::FrameResult r;
    processLegal(c.view(), r);
    EXPECT_EQ(r.label_counts[0], pts.size()) << "invalid returns must be labelled None";
    EXPECT_TRUE(r.primitives.primitives.empty());
  }
}

TEST_F(Malformed, ExtremeCoordinatesAmongGoodOnes)
{
  // huge, tiny, negative-zero and denormal coordinates: out of range or invalid returns that
  // must not overflow any float-to-integer conversion (UBSan checks this in the sanitizer build)
  auto pts = rc::test::roomScan(16, 360);
  const float extremes[] = {3e38f, -3e38f, 1e-38f, 1e-45f, -0.0f, 1e20f, 249.9f, 250.1f};
  for (std::size_t i = 0; i < pts.size(); i += 37)
  {
    const float e = extremes[(i / 37) % 8];
    pts[i].x = e;
    pts[i].y = (i % 2) ? e : -e;
  }
  const Cloud c = rc::test::pack(pts, rc::test::velodyneLayout(), 16 * 360, 1);
  rc::FrameResult r;
  processLegal(c.view(), r);
  EXPECT_EQ(r.label[0], 0) << "a 3e38 m return is out of range";
}

TEST_F(Malformed, AllPointsIdentical)
{
  for (bool same_ring : {true, false})
  {
    auto pts = rc::test::roomScan(16, 360);
    for (auto& p : pts)
    {
      p.x = 3.0f, p.y = 1.0f, p.z = 0.5f;
      if (same_ring) p.ring = 5;
    }
    const Cloud c = rc::test::pack(pts, rc::test::velodyneLayout(), 16 * 360, 1);
    rc::FrameResult r;
    processLegal(c.view(), r);
    // one position in space is one sample: nothing can bend there
    for (float k : r.curvature)
      EXPECT_TRUE(std::isnan(k) || k == 0.0f) << k;
  }
}

TEST_F(Malformed, AllPointsAtTheOrigin)
{
  auto pts = rc::test::roomScan(16, 360);
  for (auto& p : pts)
    p.x = p.y = p.z = 0.0f;
  const Cloud c = rc::test::pack(pts, rc::test::velodyneLayout(), 16 * 360, 1);
  rc::FrameResult r;
  processLegal(c.view(), r);
  EXPECT_EQ(r.label_counts[0], pts.size()) << "zero range is below min_range";
}

TEST_F(Malformed, SingleRing)
{
  const Cloud c = rc::test::pack(rc::test::roomScan(1, 1800), rc::test::velodyneLayout(), 1800, 1);
  rc::FrameResult r;
  processLegal(c.view(), r);
  // a horizontal ring in a box room sees walls almost everywhere
  EXPECT_GT(r.label_counts[static_cast<int>(rc::Label::Plane)], 1800u / 2);
}

TEST_F(Malformed, SparseRingIndices)
{
  // rings 0 and 200 only: the 199 empty rings between them must not break anything
  auto pts = rc::test::roomScan(2, 900);
  for (auto& p : pts)
    if (p.ring == 1) p.ring = 200;
  const Cloud c = rc::test::pack(pts, rc::test::velodyneLayout(), 2 * 900, 1);
  rc::FrameResult r;
  processLegal(c.view(), r);
  EXPECT_GT(r.label_counts[static_cast<int>(rc::Label::Plane)], 0u);
}

/// Runs `pts` and a permutation of it; per-point results must follow the points.
void expectOrderIndependent(const std::vector<rc::test::SyntheticPoint>& pts,
                            const std::vector<std::size_t>& perm)
{
  std::vector<rc::test::SyntheticPoint> shuffled(pts.size());
  for (std::size_t i = 0; i < perm.size(); ++i)
    shuffled[i] = pts[perm[i]];
  const auto n = static_cast<std::uint32_t>(pts.size());
  const Cloud a = rc::test::pack(pts, rc::test::velodyneLayout(), n, 1);
  const Cloud b = rc::test::pack(shuffled, rc::test::velodyneLayout(), n, 1);
  rc::FrameResult ra, rb;
  processLegal(a.view(), ra);
  processLegal(b.view(), rb);
  std::size_t label_diffs = 0, curv_diffs = 0;
  for (std::size_t i = 0; i < perm.size(); ++i)
  {
    label_diffs += ra.label[perm[i]] != rb.label[i];
    curv_diffs += !rc::test::sameFloat(ra.curvature[perm[i]], rb.curvature[i]);
  }
  EXPECT_EQ(label_diffs, 0u);
  EXPECT_EQ(curv_diffs, 0u);
  EXPECT_EQ(ra.primitives.primitives.size(), rb.primitives.primitives.size());
}

TEST_F(Malformed, AzimuthsNotMonotonic)
{
  const auto pts = rc::test::roomScan(16, 900);
  std::vector<std::size_t> perm(pts.size());
  std::iota(perm.begin(), perm.end(), 0);
  std::reverse(perm.begin(), perm.end());  // a sensor spinning the other way
  expectOrderIndependent(pts, perm);
  std::mt19937 rng(7);
  std::shuffle(perm.begin(), perm.end(), rng);  // no order at all
  expectOrderIndependent(pts, perm);
}

TEST_F(Malformed, TwoMillionPoints)
{
  const int rings = 128, samples = 15625;  // 2,000,000 points
  const Cloud c = rc::test::pack(rc::test::roomScan(rings, samples), rc::test::velodyneLayout(),
                                 rings * samples, 1);
  rc::Pipeline pipeline;
  rc::FrameResult r;
  const auto t0 = std::chrono::steady_clock::now();
  const rc::Status st = pipeline.process(c.view(), r);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(st.ok) << st.message;
  expectConsistent(r, c.size());
  EXPECT_GT(r.label_counts[static_cast<int>(rc::Label::Plane)], c.size() / 2);
  std::printf("2,000,000 points: %.2f s\n", s);
  recover(pipeline);
}

// --- equivalent layouts give equal results ----------------------------------------------------

TEST_F(Malformed, LayoutsAndTypesDoNotChangeTheResult)
{
  const auto pts = rc::test::roomScan(16, 900);
  const std::uint32_t n = 16 * 900;
  rc::FrameResult ref;
  processLegal(rc::test::pack(pts, rc::test::velodyneLayout(), n, 1).view(), ref);

  std::vector<rc::test::Layout> layouts;
  layouts.push_back(rc::test::ousterLayout());
  for (rc::ScalarType t : {rc::ScalarType::UInt8, rc::ScalarType::Int16, rc::ScalarType::Int32,
                           rc::ScalarType::UInt32})
  {
    rc::test::Layout l = rc::test::ousterLayout();
    l.ring = {32, t};
    layouts.push_back(l);
  }
  rc::test::Layout wide = rc::test::ousterLayout();  // float64 coordinates
  wide.x = {0, rc::ScalarType::Float64};
  wide.y = {8, rc::ScalarType::Float64};
  wide.z = {28, rc::ScalarType::Float64};
  wide.ring = {36, rc::ScalarType::UInt16};
  layouts.push_back(wide);
  for (const auto& l : layouts)
  {
    rc::FrameResult r;
    processLegal(rc::test::pack(pts, l, n, 1).view(), r);
    expectSameResult(r, ref);
  }
}

TEST_F(Malformed, RowPaddingIsSkipped)
{
  // row_step > width * point_step is legal; the padding (0xA5 garbage) must never be read
  const auto pts = rc::test::toOrganized(rc::test::roomScan(16, 900), 16, 900);
  rc::FrameResult a, b;
  processLegal(rc::test::pack(pts, rc::test::velodyneLayout(), 900, 16).view(), a);
  processLegal(rc::test::pack(pts, rc::test::velodyneLayout(), 900, 16, 13).view(), b);
  expectSameResult(a, b);
}

TEST_F(Malformed, ChangingFrameSizesLeaveNoStaleState)
{
  rc::Pipeline pipeline;
  rc::FrameResult r;
  for (int rings : {128, 1, 64, 16})
  {
    const Cloud c = rc::test::goodCloud(rings, 2000);
    ASSERT_TRUE(pipeline.process(c.view(), r).ok);
    expectConsistent(r, c.size());
  }
  recover(pipeline);
}

}  // namespace
