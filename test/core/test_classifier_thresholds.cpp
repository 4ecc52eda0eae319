// Thresholds: O(K) selection (selectQuantile) and each ring's thresholds, Algorithm 1's quartiles
// and the robust mode's median + k MAD with its floors, against references written the plain way.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "classification/classifier.hpp"
#include "classification/rank_select.hpp"
#include "ring_curvature/pipeline.hpp"

using namespace ring_curvature;

TEST(Classifier, SelectQuantileMatchesSortedReference)
{
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-5, 5);
  for (std::size_t n : {1u, 2u, 7u, 100u, 1001u})
  {
    std::vector<float> v(n);
    for (auto& x : v) x = u(rng);
    std::vector<float> sorted = v;
    std::sort(sorted.begin(), sorted.end());
    for (double q : {0.0, 0.25, 0.5, 0.75, 1.0})
    {
      std::vector<float> w = v;
      const std::size_t k = std::min(n - 1, static_cast<std::size_t>(q * static_cast<double>(n - 1)));
      EXPECT_EQ(selectQuantile(w.data(), n, q), sorted[k]) << n << " " << q;
    }
  }
}

namespace
{
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Test values of a few kinds: spread (exponential), duplicate-heavy, mostly zeros with tiny
// (denormal) and infinite ones, all equal, spread over the whole float range, and with negative
// values and -0 (which the ring thresholds leave to their general path).
float testValue(std::mt19937& rng, int kind)
{
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float p = u(rng);
  switch (kind)
  {
    case 0: return -std::log(1.0f - p) * 0.01f;
    case 1: return std::array<float, 5>{0.0f, 1e-3f, 0.5f, 0.5f, 2.0f}[static_cast<std::size_t>(p * 5) % 5];
    case 2: return p < 0.6f ? 0.0f : p < 0.8f ? 1e-42f * p : p < 0.9f ? kInf : p;
    case 3: return 0.25f;
    case 4: return std::pow(10.0f, 76.0f * p - 38.0f);
    default: return p < 0.1f ? -0.0f : p < 0.2f ? 0.0f : p < 0.3f ? -kInf : (p - 0.5f) * 8.0f;
  }
}
constexpr int kKinds = 6;
}  // namespace

TEST(Classifier, SelectQuantileMatchesNthElement)
{
  // the sizes cover a single value, the nth_element-only path, one and several radix passes and
  // more candidates than fit the local buffer
  std::mt19937 rng(5);
  for (std::size_t n : {1u, 2u, 31u, 33u, 100u, 1000u, 9000u})
    for (int kind = 0; kind < kKinds; ++kind)
    {
      std::vector<float> v(n);
      for (auto& x : v) x = testValue(rng, kind);
      for (double q : {0.0, 0.25, 0.3, 0.5, 0.75, 1.0})
      {
        std::vector<float> ref = v, w = v;
        const std::size_t k = std::min(n - 1, static_cast<std::size_t>(q * static_cast<double>(n - 1)));
        std::nth_element(ref.begin(), ref.begin() + static_cast<std::ptrdiff_t>(k), ref.end());
        EXPECT_EQ(selectQuantile(w.data(), n, q), ref[k]) << n << " " << kind << " " << q;
        // reordered, never overwritten
        std::vector<float> a = v;
        auto bitsLess = [](float x, float y) { return std::memcmp(&x, &y, sizeof x) < 0; };
        std::sort(a.begin(), a.end(), bitsLess);
        std::sort(w.begin(), w.end(), bitsLess);
        EXPECT_EQ(std::memcmp(a.data(), w.data(), n * sizeof(float)), 0) << n << " " << kind << " " << q;
      }
    }
}

TEST(Classifier, RingThresholdsMatchNthElementReference)
{
  // Rings of every kind and size (NaN where a feature is undefined), against the thresholds
  // defined the plain way: nearest-rank selection by nth_element over the finite values.
  std::mt19937 rng(9);
  ScanGrid grid;
  Features f;
  grid.ring_begin.push_back(0);
  for (std::size_t n : {0u, 1u, 5u, 40u, 300u, 2000u})
    for (int kind = 0; kind < kKinds; ++kind)
    {
      for (std::size_t i = 0; i < n; ++i)
      {
        const bool undefined = rng() % 16 == 0;
        f.turning.push_back(undefined ? kNaN : testValue(rng, kind));
        f.curvature.push_back(undefined ? kNaN : testValue(rng, kind));
        f.smoothness.push_back(rng() % 16 == 0 ? kNaN : testValue(rng, kind));
        f.discontinuity.push_back(rng() % 16 == 0 ? kNaN : testValue(rng, kind));
      }
      grid.ring_begin.push_back(static_cast<std::uint32_t>(f.turning.size()));
    }
  grid.num_rings = static_cast<int>(grid.ring_begin.size()) - 1;
  auto finite = [&](const std::vector<float>& v, int ring) {
    std::vector<float> out;
    for (std::uint32_t p = grid.ring_begin[ring]; p < grid.ring_begin[ring + 1]; ++p)
      if (std::isfinite(v[p])) out.push_back(v[p]);
    return out;
  };
  auto nth = [](std::vector<float> v, double q) {
    const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1)));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k];
  };
  Params P;
  P.edge_min_angle_deg = -kInf;  // no floors but the smoothness one, 0 for range_noise 0
  P.jump_min_ratio = -kInf;
  P.range_noise = 0.0f;
  Classifier c;
  std::vector<RingThresholds> thr;
  c.computeThresholds(grid, f, P, thr);
  for (int ring = 0; ring < grid.num_rings; ++ring)
  {
    auto robust = [&](const std::vector<float>& feature, float floor) {
      const std::vector<float> v = finite(feature, ring);
      if (v.empty()) return floor;
      const float med = nth(v, 0.5);
      std::vector<float> d;
      for (float x : v) d.push_back(std::fabs(x - med));
      return std::max(med + P.robust_k * 1.4826f * nth(d, 0.5), floor);
    };
    const RingThresholds& t = thr[static_cast<std::size_t>(ring)];
    EXPECT_EQ(t.curvature_high, robust(f.turning, -kInf)) << ring;
    EXPECT_EQ(t.smoothness_high, robust(f.smoothness, 0.0f)) << ring;
    EXPECT_EQ(t.discontinuity_high, robust(f.discontinuity, -kInf)) << ring;
  }
  P.classifier_mode = ClassifierMode::Quartile;
  c.computeThresholds(grid, f, P, thr);
  for (int ring = 0; ring < grid.num_rings; ++ring)
  {
    auto quartile = [&](const std::vector<float>& feature, double q) {
      const std::vector<float> v = finite(feature, ring);
      return v.empty() ? kInf : nth(v, q);
    };
    const RingThresholds& t = thr[static_cast<std::size_t>(ring)];
    EXPECT_EQ(t.curvature_low, quartile(f.curvature, 0.25)) << ring;
    EXPECT_EQ(t.curvature_high, quartile(f.curvature, 0.75)) << ring;
    EXPECT_EQ(t.smoothness_high, quartile(f.smoothness, 0.75)) << ring;
    EXPECT_EQ(t.discontinuity_low, quartile(f.discontinuity, 0.25)) << ring;
    EXPECT_EQ(t.discontinuity_high, quartile(f.discontinuity, 0.75)) << ring;
  }
}

TEST(Classifier, RobustFloorsMatchTheExactThresholds)
{
  // The robust mode decides "the floor wins" from upper bounds of the median and MAD where it
  // can (two counts, or the histogram) and computes them exactly otherwise: with floors below,
  // near and above each ring's exact median + k MAD, every threshold must equal the reference.
  std::mt19937 rng(11);
  ScanGrid grid;
  Features f;
  grid.ring_begin.push_back(0);
  for (std::size_t n : {3u, 40u, 300u, 2000u})
    for (int kind = 0; kind < kKinds; ++kind)
      for (int scale = 0; scale < 3; ++scale)  // the same shapes at three magnitudes
      {
        const float s = std::array<float, 3>{1e-3f, 1.0f, 30.0f}[static_cast<std::size_t>(scale)];
        for (std::size_t i = 0; i < n; ++i)
        {
          f.turning.push_back(rng() % 16 == 0 ? kNaN : s * testValue(rng, kind));
          f.curvature.push_back(kNaN);
          f.smoothness.push_back(rng() % 16 == 0 ? kNaN : s * testValue(rng, kind));
          f.discontinuity.push_back(rng() % 16 == 0 ? kNaN : s * testValue(rng, kind));
        }
        grid.ring_begin.push_back(static_cast<std::uint32_t>(f.turning.size()));
      }
  grid.num_rings = static_cast<int>(grid.ring_begin.size()) - 1;
  auto exact = [&](const std::vector<float>& feature, int ring, float k, float floor) {
    std::vector<float> v;
    for (std::uint32_t p = grid.ring_begin[ring]; p < grid.ring_begin[ring + 1]; ++p)
      if (std::isfinite(feature[p])) v.push_back(feature[p]);
    if (v.empty()) return floor;
    const float med = selectQuantile(std::vector<float>(v).data(), v.size(), 0.5);
    for (float& x : v) x = std::fabs(x - med);
    return std::max(med + k * 1.4826f * selectQuantile(v.data(), v.size(), 0.5), floor);
  };
  Classifier c;
  std::vector<RingThresholds> thr;
  for (float k : {0.0f, 3.0f})
    for (float floor : {1e-6f, 1e-4f, 1e-3f, 3e-3f, 0.01f, 0.03f, 0.1f, 0.3f, 1.0f, 3.0f, 10.0f, 100.0f})
    {
      Params P;
      P.robust_k = k;
      P.edge_min_angle_deg = floor / 0.0174532925f;
      P.jump_min_ratio = floor;
      P.noise_floor_k = 1.0f;
      P.range_noise = std::sqrt(floor);
      c.computeThresholds(grid, f, P, thr);
      const float turn_floor = P.edge_min_angle_deg * 0.0174532925f;
      const float smooth_floor = (P.noise_floor_k * P.range_noise) * (P.noise_floor_k * P.range_noise);
      for (int ring = 0; ring < grid.num_rings; ++ring)
      {
        const RingThresholds& t = thr[static_cast<std::size_t>(ring)];
        EXPECT_EQ(t.curvature_high, exact(f.turning, ring, k, turn_floor)) << ring << " " << floor;
        EXPECT_EQ(t.smoothness_high, exact(f.smoothness, ring, k, smooth_floor)) << ring << " " << floor;
        EXPECT_EQ(t.discontinuity_high, exact(f.discontinuity, ring, k, floor)) << ring << " " << floor;
      }
    }
}
