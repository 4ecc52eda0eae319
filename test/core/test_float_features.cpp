// The default modes' curvature and discontinuity (Chord, Jump) are computed in float (eight
// lanes): they must stay within float's reach of the same formulas in double, written here
// independently of the code under test, from 0.5 m to 200 m and across a closed ring's seam.
// Float's reach is measured in units of the range's rounding: eps = 2^-24 of the range, over the
// chord's length for the turning angle and arc length (the same order as the float32 input's own
// quantization of the coordinates), over the range for the jump.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "../support/synthetic_cloud.hpp"
#include "common/float_bits.hpp"
#include "ring_curvature/pipeline.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
constexpr double kPi = 3.14159265358979323846;

double wrap(double a) { return a >= kPi ? a - 2 * kPi : (a < -kPi ? a + 2 * kPi : a); }

// Closed rings of 1800 samples, 0.2 deg apart, around an irregular room of mean range `r0`: a
// wavy wall with a depth step and a few centimetres of deterministic roughness; ring 1 lies on a
// cone (elevation about -15 deg) so that the development factor is not 1. With `gaps`, holes of
// 1 to 6 missing samples (those of 3 or more break the ring's curve), their pattern shifted by
// `shift` samples (448 puts a gap of three right after the seam).
SyntheticCloud roomRings(double r0, bool gaps = false, int shift = 0)
{
  SyntheticCloud cloud;  // float32, the drivers' type
  const int n = 1800;
  for (int ring = 0; ring < 2; ++ring)
    for (int j = 0; j < n; ++j)
    {
      if (gaps && (j + shift) % 150 < ((j + shift) / 150) % 7) continue;
      const double th = -kPi + 2 * kPi * (j + 0.25) / n;
      double rho = r0 * (1.0 + 0.3 * std::sin(3 * th) + (j % 400 < 200 ? 0.0 : 0.08));
      rho += 0.004 * r0 * std::sin(j * 2.3) * std::cos(j * 0.7);
      const double z = ring == 0 ? 0.0 : -0.27 * rho;
      cloud.add(rho * std::cos(th), rho * std::sin(th), z, ring);
    }
  return cloud;
}

constexpr double kEps = 1.0 / (1 << 24);

// Largest deviations, in units of the range's float rounding (see above).
struct Deviation
{
  double turning = 0, length = 0, jump = 0;
  int compared = 0;
};

// The chord-mode turning angle, arc length and jump link of every sample in double, from the
// grid's double ranges and float azimuths, compared with the pipeline's float features.
Deviation compareWithDouble(const Pipeline& pipe, const Params& P)
{
  const ScanGrid& g = pipe.grid();
  const Features& f = pipe.features();
  Deviation dev;
  const double res = g.azimuth_resolution;
  for (int n = 0; n < g.num_rings; ++n)
  {
    const int b = static_cast<int>(g.ring_begin[n]), K = static_cast<int>(g.ringSize(n));
    const double c = g.ring_cos[n];
    const auto at = [&](int k) { return b + ((k % K) + K) % K; };
    for (int k = 0; k < K; ++k)
    {
      const int p = at(k);
      const double rho = g.range[p];
      const double q = P.chord_length / (rho * c * res);
      // a quotient within rounding of an integer may take the next sample count in float
      if (std::fabs(q - std::round(q)) < 1e-4) continue;
      const int h = std::clamp(static_cast<int>(std::ceil(q)), 1, P.max_chord_samples);
      const int pp = at(k - h), pn = at(k + h);
      const double ap = c * wrap(static_cast<double>(g.azimuth[pp]) - g.azimuth[p]);
      const double an = c * wrap(static_cast<double>(g.azimuth[pn]) - g.azimuth[p]);
      const double vx = rho - g.range[pp] * std::cos(ap), vy = -g.range[pp] * std::sin(ap);
      const double ux = g.range[pn] * std::cos(an) - rho, uy = g.range[pn] * std::sin(an);
      // fastAtan2 as in the code (~1e-5 rad off atan2), on the double products: the comparison
      // then sees the float chords' error alone
      const double turn =
          std::fabs(fastAtan2(static_cast<float>(vx * uy - vy * ux), static_cast<float>(vx * ux + vy * uy)));
      const double len = 0.5 * (std::hypot(vx, vy) + std::hypot(ux, uy));
      // the jump of link (k - 1, k), the smaller of both sides' linear predictions
      const double r0 = g.range[at(k - 1)], rm = g.range[at(k - 2)], r2 = g.range[at(k + 1)];
      const double jump = std::min(std::fabs(rho - (2 * r0 - rm)), std::fabs(r0 - (2 * rho - r2))) / std::min(r0, rho);
      const double jump_next = [&] {
        const double s1 = g.range[at(k + 1)], s2 = g.range[at(k + 2)], sm = g.range[at(k - 1)];
        return std::min(std::fabs(s1 - (2 * rho - sm)), std::fabs(rho - (2 * s1 - s2))) / std::min(rho, s1);
      }();
      const double unit = kEps * rho / std::min({std::hypot(vx, vy), std::hypot(ux, uy), len});
      dev.turning = std::max(dev.turning, std::fabs(f.turning[p] - turn) / unit);
      dev.length = std::max(dev.length, std::fabs(f.turning[p] / f.curvature[p] / len - 1.0) / unit);
      dev.jump = std::max(dev.jump, std::fabs(f.discontinuity[p] - std::max(jump, jump_next)) / kEps);
      ++dev.compared;
    }
  }
  return dev;
}

// Detrended residual variance of ranges [a, b] of a ring (wrapped), two-pass in double.
double detrendedVariance(const ScanGrid& g, int b0, int K, int a, int b)
{
  const int n = b - a + 1;
  const auto r = [&](int k) { return g.range[b0 + ((k % K) + K) % K]; };
  double mean = 0, jbar = 0.5 * (a + b);
  for (int k = a; k <= b; ++k) mean += r(k) / n;
  double sjj = 0, sjr = 0;
  for (int k = a; k <= b; ++k)
  {
    sjj += (k - jbar) * (k - jbar);
    sjr += (k - jbar) * (r(k) - mean);
  }
  const double slope = n >= 3 ? sjr / sjj : 0.0;
  double ss = 0;
  for (int k = a; k <= b; ++k)
  {
    const double e = r(k) - mean - slope * (k - jbar);
    ss += e * e;
  }
  return ss / n;
}
}  // namespace

// The default smoothness (Detrended, window 3) is formed in float from ranges relative to each
// window's centre sample, never from sums of squared ranges: against a two-pass double reference
// it must stay within a few float roundings of the window's range differences m and of the range
// itself, eps (m^2 + m rho). Sums of the ranges themselves in float would be off by ~eps rho^2.
TEST(FloatFeatures, DetrendedSmoothnessMatchesDouble)
{
  // shift 448: near-gap windows that reach across the seam (the ranges wrapped one by one)
  for (const int shift : {0, 448})
  for (const double r0 : {0.5, 3.0, 20.0, 80.0, 200.0})
  {
    const SyntheticCloud cloud = roomRings(r0, true, shift);
    Params params;
    params.max_range = 300.0f;
    Pipeline pipe(params);
    FrameResult res;
    ASSERT_TRUE(pipe.process(cloud.view(), res).ok);
    const ScanGrid& g = pipe.grid();
    const int w = params.smoothness_window;
    double worst = 0;
    int near_gap = 0, across_seam = 0;
    for (int ring = 0; ring < g.num_rings; ++ring)
    {
      const int b0 = static_cast<int>(g.ring_begin[ring]), K = static_cast<int>(g.ringSize(ring));
      ASSERT_TRUE(g.ring_closed[ring]);
      const auto linked = [&](int k) { return g.linked[b0 + ((k % K) + K) % K] != 0; };
      for (int k = 0; k < K; ++k)
      {
        int a = 0, z = 0;  // the window's reach, left and right, up to w and not across a gap
        while (a < w && linked(k - a)) ++a;
        while (z < w && linked(k + z + 1)) ++z;
        near_gap += a < w || z < w;
        across_seam += (a < w || z < w) && (k - a < 0 || k + z >= K);
        if (a + z == 0) continue;
        double want = detrendedVariance(g, b0, K, k - a, k + z);
        if (a >= 2) want = std::min(want, detrendedVariance(g, b0, K, k - a, k));
        if (z >= 2) want = std::min(want, detrendedVariance(g, b0, K, k, k + z));
        double m = 0;
        for (int j = -a; j <= z; ++j) m = std::max(m, std::fabs(g.range[b0 + ((k + j) % K + K) % K] - g.range[b0 + k]));
        const double unit = kEps * (m * m + m * g.range[b0 + k]) + 1e-30;
        worst = std::max(worst, std::fabs(pipe.features().smoothness[b0 + k] - want) / unit);
      }
    }
    std::printf("shift %d, r0 %6.1f m: %d samples near a gap, %d across the seam; largest smoothness deviation "
                "%.2f eps units\n",
                shift, r0, near_gap, across_seam, worst);
    EXPECT_GT(near_gap, 50) << "r0 " << r0;
    if (shift != 0)
    {
      EXPECT_GT(across_seam, 0) << "r0 " << r0;
    }
    EXPECT_LT(worst, 8.0) << "r0 " << r0;
  }
}

// Longest chords of 6 samples (the default), 16 and 17; at 0.5 m every chord is the longest, at 3 m and beyond the sample counts vary along the wall. The
// rings' 1800 samples leave a tail of 8 past the last group of sixteen.
TEST(FloatFeatures, ChordAndJumpMatchDoubleFormulas)
{
  for (const int max_h : {6, 16, 17})
    for (const double r0 : {0.5, 1.2, 3.0, 8.0, 20.0, 80.0, 200.0})
    {
      const SyntheticCloud cloud = roomRings(r0);
      Params params;  // defaults: Chord, Detrended, Jump
      params.max_range = 300.0f;
      params.max_chord_samples = max_h;
      Pipeline pipe(params);
      FrameResult res;
      ASSERT_TRUE(pipe.process(cloud.view(), res).ok);
      ASSERT_EQ(pipe.grid().num_rings, 2);
      ASSERT_TRUE(pipe.grid().ring_closed[0] && pipe.grid().ring_closed[1]);
      const Deviation d = compareWithDouble(pipe, params);
      std::printf("max %2d samples, r0 %6.1f m: %d samples, largest deviations in eps units: turning %.2f, arc length "
                  "%.2f, jump %.2f\n",
                  max_h, r0, d.compared, d.turning, d.length, d.jump);
      EXPECT_GT(d.compared, 3000) << "r0 " << r0 << ", max " << max_h;
      EXPECT_LT(d.turning, 8.0) << "r0 " << r0 << ", max " << max_h;
      EXPECT_LT(d.length, 8.0) << "r0 " << r0 << ", max " << max_h;
      EXPECT_LT(d.jump, 8.0) << "r0 " << r0 << ", max " << max_h;
    }
}

// The near-gap windows of the default smoothness (nearGapDirect: in double, the centred and the
// left window summed in one pass, a one-sided window equal to the centred one not formed again)
// bit for bit against their definition written here: each window's ranges relative to its first,
// summed in index order, its residual variance with 1 / n and the trend factor (none for two
// samples), the smaller of the centred and the one-sided windows of 3 or more samples. Rings of
// segments of 1 to 9 samples between holes of 4 give every reach (0 to w on each side) and single
// samples.
TEST(FloatFeatures, NearGapSmoothnessBitForBit)
{
  SyntheticCloud cloud;
  const int n = 1800;
  for (int ring = 0; ring < 2; ++ring)
  {
    int len = 1 + ring, run = 0;  // current segment's length, samples placed in it
    for (int j = 0; j < n; ++j)
    {
      if (run == len)
      {
        j += 3;  // a hole of 4 samples
        run = 0;
        len = len % 9 + 1;
        continue;
      }
      ++run;
      const double th = -kPi + 2 * kPi * (j + 0.25) / n;
      const double rho = 5.0 * (1.0 + 0.3 * std::sin(3 * th)) + 0.02 * std::sin(j * 2.3) * std::cos(j * 0.7);
      cloud.add(rho * std::cos(th), rho * std::sin(th), ring == 0 ? 0.0 : -0.27 * rho, ring);
    }
  }
  Params params;
  Pipeline pipe(params);
  FrameResult res;
  ASSERT_TRUE(pipe.process(cloud.view(), res).ok);
  const ScanGrid& g = pipe.grid();
  const int w = params.smoothness_window;
  int compared = 0, single = 0, at_gap = 0;
  for (int ring = 0; ring < g.num_rings; ++ring)
  {
    const int b0 = static_cast<int>(g.ring_begin[ring]), K = static_cast<int>(g.ringSize(ring));
    const auto r = [&](int k) { return g.range[b0 + ((k % K) + K) % K]; };
    const auto linked = [&](int k) { return g.linked[b0 + ((k % K) + K) % K] != 0; };
    const auto window = [&](int first, int cnt) {
      const double ref = r(first), jbar = 0.5 * (cnt - 1);
      double s0 = 0, s1 = 0, s2 = 0;
      for (int j = 0; j < cnt; ++j)
      {
        const double d = r(first + j) - ref;
        s0 += d;
        s1 += (j - jbar) * d;
        s2 += d * d;
      }
      // no trend removed from a window of two (it would leave nothing)
      const double c = cnt, ic = 1.0 / c, it = cnt >= 3 ? 1.0 / ((c * c - 1.0) * c * (1.0 / 12.0) * c) : 0.0;
      const double mean = s0 * ic;
      return std::max(0.0, s2 * ic - mean * mean - s1 * s1 * it);
    };
    for (int k = 0; k < K; ++k)
    {
      int a = 0, z = 0;
      while (a < w && linked(k - a)) ++a;
      while (z < w && linked(k + z + 1)) ++z;
      if (a == w && z == w) continue;
      float want = 0.0f;
      if (a + z > 0)
      {
        double v = window(k - a, a + z + 1);
        if (a + 1 >= 3) v = std::min(v, window(k - a, a + 1));
        if (z + 1 >= 3) v = std::min(v, window(k, z + 1));
        want = static_cast<float>(v);
      }
      single += a + z == 0;
      at_gap += (a == 0) != (z == 0);
      ++compared;
      ASSERT_EQ(want, pipe.features().smoothness[b0 + k])
          << "ring " << ring << " sample " << k << " a " << a << " z " << z;
    }
  }
  EXPECT_GT(single, 20);
  EXPECT_GT(at_gap, 100);
  EXPECT_GT(compared, 1000);
}
