// Issue 30 (item 1): the sweep times of LOAM's feature sets (loam/loam_selector.cpp): from the
// azimuth, either way round, when the cloud has no usable time field, and from the field (float32
// seconds, uint32 nanoseconds) held to the scan period.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>
#include "ring_curvature/pipeline.hpp"
#include "../support/loam_run.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{

double circularGap(double a, double b, double period)
{
  const double d = std::fabs(a - b);
  return std::min(d, period - d);
}

TEST(LoamFeatures, SweepTimeFromAzimuth)
{
  const double start = 1.0;  // the first input point is not at the grid's seam (-pi)
  Params P = baseParams();
  P.scan_period = 0.1f;
  LoamRun run(boxScene(), P, 0.0, start);
  const ScanGrid& g = run.grid();
  ASSERT_EQ(run.f.cloud.size(), 16u * 1800u);
  ASSERT_EQ(run.f.column[0], 0);
  ASSERT_GE(run.f.hits[0].object, 0);  // the first input point is a return

  const auto check = [&](const LoamFeatures& L, bool clockwise, double period, const char* what) {
    EXPECT_FALSE(L.time_from_field) << what;
    ASSERT_EQ(L.sweep_time.size(), g.size());
    double worst = 0;
    for (std::uint32_t p = 0; p < g.size(); ++p)
    {
      const double t = L.sweep_time[p];
      EXPECT_GE(t, 0.0) << what;
      EXPECT_LE(t, period) << what;
      const double k = run.f.column[g.index[p]];  // azimuth = start + k * 2 pi / 1800
      const double frac = clockwise ? (k == 0 ? 0.0 : 1.0 - k / 1800) : k / 1800;
      worst = std::max(worst, circularGap(t, frac * period, period));
    }
    EXPECT_LT(worst, 2e-6 * period / 0.1) << what;
    // the point fired a quarter turn after the first (counter-clockwise in this scan)
    const std::uint32_t q = static_cast<std::uint32_t>(g.grid_pos[450]);
    EXPECT_NEAR(L.sweep_time[q], (clockwise ? 0.75 : 0.25) * period, 1e-5) << what;
  };
  check(run.loam, true, static_cast<double>(P.scan_period), "constant 0 s, clockwise");

  // Without any time field: the same.
  PointCloudView v = run.f.cloud.view();
  v.time = FieldView{};
  LoamFeatures L;
  run.pipe.selectLoamFeatures(v, L);
  check(L, true, static_cast<double>(P.scan_period), "no time field, clockwise");

  // Counter-clockwise and another period.
  P.sweep_clockwise = false;
  P.scan_period = 0.05f;
  check(run.reselect(P), false, static_cast<double>(P.scan_period), "counter-clockwise");

  // A constant non-zero field is no time either.
  for (std::size_t i = 0; i < run.f.cloud.size(); ++i) run.f.cloud.setTime(i, 5.0f);
  run.pipe.selectLoamFeatures(run.f.cloud.view(), L);
  check(L, false, static_cast<double>(P.scan_period), "constant 5 s");
}

TEST(LoamFeatures, SweepTimeFromTheField)
{
  Params P = baseParams();
  LoamRun run(boxScene(), P);
  const ScanGrid& g = run.grid();
  SyntheticCloud& c = run.f.cloud;
  const std::size_t n = c.size();

  // float32 seconds, from 0.5 s (a frame stamped within a longer recording)
  for (std::size_t i = 0; i < n; ++i) c.setTime(i, 0.5f + 0.09f * static_cast<float>(run.f.column[i]) / 1800.0f);
  LoamFeatures L;
  run.pipe.selectLoamFeatures(c.view(), L);
  EXPECT_TRUE(L.time_from_field);
  const auto timeOf = [&](std::uint32_t p) {  // the field as written, as float32
    return static_cast<double>(0.5f + 0.09f * static_cast<float>(run.f.column[g.index[p]]) / 1800.0f);
  };
  double lo = 1e9;
  for (std::uint32_t p = 0; p < g.size(); ++p) lo = std::min(lo, timeOf(p));
  double worst = 0;
  for (std::uint32_t p = 0; p < g.size(); ++p) worst = std::max(worst, std::fabs(L.sweep_time[p] - (timeOf(p) - lo)));
  EXPECT_LT(worst, 1e-6) << "float32 seconds";
  EXPECT_GT(*std::max_element(L.sweep_time.begin(), L.sweep_time.end()), 0.089f);

  // uint32 nanoseconds (Ouster's t), scale 1e-9
  for (std::size_t i = 0; i < n; ++i)
    c.setTimeUInt32(i, 1000u + static_cast<std::uint32_t>(std::lround(9.5e7 * run.f.column[i] / 1800.0)));
  PointCloudView v = c.view();
  v.time.type = ScalarType::UInt32;
  v.time_scale = 1e-9;
  run.pipe.selectLoamFeatures(v, L);
  EXPECT_TRUE(L.time_from_field);
  std::uint32_t ulo = ~0u;
  const auto nsOf = [&](std::uint32_t p) {
    return 1000u + static_cast<std::uint32_t>(std::lround(9.5e7 * run.f.column[g.index[p]] / 1800.0));
  };
  for (std::uint32_t p = 0; p < g.size(); ++p) ulo = std::min(ulo, nsOf(p));
  worst = 0;
  for (std::uint32_t p = 0; p < g.size(); ++p)
    worst = std::max(worst, std::fabs(L.sweep_time[p] - (nsOf(p) - ulo) * 1e-9));
  EXPECT_LT(worst, 1e-7) << "uint32 nanoseconds";

  // A field spanning more than the period is held to [0, scan_period].
  for (std::size_t i = 0; i < n; ++i) c.setTime(i, 0.3f * static_cast<float>(run.f.column[i]) / 1800.0f);
  run.pipe.selectLoamFeatures(c.view(), L);
  EXPECT_TRUE(L.time_from_field);
  std::size_t at_end = 0;
  for (const float t : L.sweep_time)
  {
    EXPECT_GE(t, 0.0f);
    EXPECT_LE(t, P.scan_period);
    at_end += t == P.scan_period;
  }
  EXPECT_GT(at_end, g.size() / 2);
}

}  // namespace
