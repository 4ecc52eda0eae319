// Labels: the rules point by point in every mode, non-maximum suppression run by run, Algorithm 1's
// proportions and the robust mode on clean geometry, vegetation (the thresholds and their O(K)
// selection: test_classifier_thresholds.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "../support/ray_scene.hpp"
#include "classification/classifier.hpp"
#include "ring_curvature/pipeline.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
}  // namespace

TEST(Classifier, LabelsFollowTheRulesPointByPoint)
{
  // The vectorized labelling against the rules written out per point, in every mode and
  // ablation (non-max suppression off: it only demotes Edges afterwards).
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  ScanGrid grid;
  Features f;
  grid.ring_begin = {0};
  for (int ring = 0; ring < 8; ++ring)
  {
    for (int i = 0; i < 500 + 37 * ring; ++i)
    {
      auto value = [&](float scale) { return u(rng) < 0.05f ? kNaN : scale * std::pow(u(rng), 3.0f); };
      f.turning.push_back(value(1.0f));
      f.curvature.push_back(u(rng) < 0.02f ? 0.0f : value(5.0f));
      f.smoothness.push_back(value(1e-3f));
      f.discontinuity.push_back(value(0.2f));
      grid.range.push_back(0.5 + 30.0 * static_cast<double>(u(rng)));
      grid.index.push_back(static_cast<std::uint32_t>(grid.index.size()));
    }
    grid.ring_begin.push_back(static_cast<std::uint32_t>(grid.index.size()));
  }
  grid.num_rings = 8;
  for (int mode = 0; mode < 12; ++mode)
  {
    Params P;
    P.non_max_suppression = false;
    P.classifier_mode = mode < 4 ? ClassifierMode::Quartile : ClassifierMode::Robust;
    P.discontinuity_mode = mode >= 8 ? DiscontinuityMode::Paper : DiscontinuityMode::Jump;
    P.use_curvature = mode % 4 != 1;
    P.use_smoothness = mode % 4 != 2;
    P.edge_min_angle_deg = 5.0f;
    Classifier c;
    std::vector<RingThresholds> thr;
    std::vector<Label> labels;
    c.computeThresholds(grid, f, P, thr);
    c.classify(grid, f, P, thr, labels);
    const float noise = P.noise_floor_k * 2.45f * P.range_noise;
    for (int ring = 0; ring < grid.num_rings; ++ring)
      for (std::uint32_t p = grid.ring_begin[ring]; p < grid.ring_begin[ring + 1]; ++p)
      {
        const RingThresholds& t = thr[static_cast<std::size_t>(ring)];
        const float kappa = P.use_curvature ? f.curvature[p] : kNaN;
        const float S = P.use_smoothness ? f.smoothness[p] : kNaN, D = f.discontinuity[p];
        Label l = Label::Plane;
        if (std::isnan(f.smoothness[p]) && std::isnan(f.curvature[p]) && std::isnan(D))
          l = Label::None;
        else if (P.classifier_mode == ClassifierMode::Quartile)
        {
          if (S > t.smoothness_high)
            l = Label::Rough;
          else if ((kappa < t.curvature_low || !P.use_curvature) && D < t.discontinuity_low)
            l = Label::Plane;
          else if ((kappa > t.curvature_high || !P.use_curvature) && D > t.discontinuity_high)
            l = Label::Corner;
          else if (kappa > t.curvature_high)
            l = Label::Edge;
        }
        else
        {
          const float turn = P.use_curvature ? f.turning[p] : kNaN;
          const float chord = kappa > 0 ? turn / kappa : 0.0f;
          bool jump_high = D > t.discontinuity_high;
          if (P.discontinuity_mode == DiscontinuityMode::Jump)
            jump_high = jump_high && static_cast<double>(D) * grid.range[p] > static_cast<double>(noise);
          if (S > t.smoothness_high)
            l = Label::Rough;
          else if (jump_high)
            l = Label::Corner;
          else if (turn > t.curvature_high && turn * chord > noise)
            l = Label::Edge;
        }
        ASSERT_EQ(static_cast<int>(labels[p]), static_cast<int>(l)) << "mode " << mode << " at " << p;
      }
  }
}

namespace
{
// Level ground and a few walls, noise 1 cm: a clean planar scene.
ScannedFrame planarScene()
{
  RayScene s;
  s.boxes.push_back({12.0, 0.0, -1.8, 3.0, 0.2, 8.0, 0.3});
  s.boxes.push_back({-9.0, 4.0, -1.8, 3.0, 0.2, 6.0, -0.5});
  return scan(s, SensorModel::uniform(16, -15, 15, 0.2), 0.01, 11);
}
double share(const FrameResult& r, Label l)
{
  const auto c = std::count(r.label.begin(), r.label.end(), static_cast<std::uint8_t>(l));
  std::size_t valid = 0;
  for (auto x : r.label) valid += x != 0 ? 1 : 0;
  return static_cast<double>(c) / static_cast<double>(valid);
}
}  // namespace

TEST(Classifier, QuartileModeForcesAQuarterRoughRobustModeDoesNot)
{
  const ScannedFrame f = planarScene();
  Params quartile;
  quartile.classifier_mode = ClassifierMode::Quartile;
  quartile.curvature_mode = CurvatureMode::Paper;
  quartile.smoothness_mode = SmoothnessMode::Variance;
  quartile.discontinuity_mode = DiscontinuityMode::Paper;
  Pipeline pq(quartile), pr;
  FrameResult rq, rr;
  ASSERT_TRUE(pq.process(f.cloud.view(), rq).ok);
  ASSERT_TRUE(pr.process(f.cloud.view(), rr).ok);
  std::printf("quartile: plane %.3f rough %.3f edge %.3f corner %.3f | robust: plane %.3f rough %.3f edge %.3f corner %.3f\n",
              share(rq, Label::Plane), share(rq, Label::Rough), share(rq, Label::Edge), share(rq, Label::Corner),
              share(rr, Label::Plane), share(rr, Label::Rough), share(rr, Label::Edge), share(rr, Label::Corner));
  // READING_NOTES 6: by construction about a quarter of every ring is Rough under Algorithm 1
  EXPECT_GT(share(rq, Label::Rough), 0.2);
  EXPECT_LT(share(rq, Label::Rough), 0.3);
  // the robust mode calls a clean planar scene planar
  EXPECT_GT(share(rr, Label::Plane), 0.95);
  EXPECT_LT(share(rr, Label::Rough), 0.02);
}

TEST(Classifier, VegetationIsRough)
{
  // A wall behind a "hedge": random returns in a 1 m deep volume in front of part of it.
  SyntheticCloud c;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> depth(0.0, 1.0);
  const double step = 0.2 * 3.14159265358979323846 / 180;
  std::size_t hedge_total = 0, hedge_rough = 0;
  std::vector<int> is_hedge;
  for (int n = 0; n < 8; ++n)
  {
    const double phi = (-7 + 2 * n) * 3.14159265358979323846 / 180;
    for (int k = 0; k < 1800; ++k)
    {
      const double th = -3.14159265358979323846 + k * step;
      double dx, dy, dz;
      beamDir(phi, th, dx, dy, dz);
      const double wall = 10.0 / std::max(0.2, std::fabs(std::cos(th)));  // rough room of walls
      double t = wall;
      const bool hedge = std::fabs(th) < 0.3;
      if (hedge) t = 8.0 + depth(rng);
      c.add(t * dx, t * dy, t * dz, n);
      is_hedge.push_back(hedge ? 1 : 0);
    }
  }
  Pipeline p;
  FrameResult r;
  ASSERT_TRUE(p.process(c.view(), r).ok);
  for (std::size_t i = 0; i < is_hedge.size(); ++i)
    if (is_hedge[i])
    {
      ++hedge_total;
      hedge_rough += r.label[i] == static_cast<std::uint8_t>(Label::Rough) ? 1 : 0;
    }
  std::printf("hedge points Rough: %zu / %zu\n", hedge_rough, hedge_total);
  EXPECT_GT(static_cast<double>(hedge_rough) / static_cast<double>(hedge_total), 0.6);
}

namespace
{
// The input of the non-max suppression test (below): rings of stretches of features (Edges,
// turning above 0.5 with a short chord, and Corners) and of other samples (Plane, Rough), linked
// or not, and a ring whose last samples and first ones are one run across the seam.
struct RunRings
{
  ScanGrid grid;
  Features f;
  int rings = 0;
};

RunRings runRings()
{
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  RunRings out;
  ScanGrid& grid = out.grid;
  Features& f = out.f;
  grid.ring_begin = {0};
  const int sizes[] = {700, 0, 1, 2, 9, 517, 64, 333, 40, 256, 129};
  const int rings = static_cast<int>(sizeof sizes / sizeof sizes[0]);
  const std::uint8_t links[] = {1, 1, 1, 2, 0x80, 0xFF};
  for (int ring = 0; ring < rings; ++ring)
  {
    const bool all_one_run = ring == 8;
    int left = 0;  // samples left in the current stretch
    bool feature = false;
    for (int i = 0; i < sizes[ring]; ++i)
    {
      if (left == 0)
      {
        feature = all_one_run || !feature;
        left = 1 + static_cast<int>(u(rng) * (u(rng) < 0.5f ? 3.0f : 19.0f));
      }
      --left;
      const float kind = u(rng);
      const bool corner = feature && kind < 0.08f, rough = !feature && kind < 0.1f;
      // Edge: turning above 0.5 and a short chord; Plane below it
      f.turning.push_back(feature && !corner ? 0.6f + std::floor(u(rng) * 8.0f) / 8.0f : 0.1f * u(rng));
      f.curvature.push_back(0.01f);
      f.smoothness.push_back(rough ? 0.9f : 0.0f);
      f.discontinuity.push_back(corner ? 0.9f : 0.0f);
      grid.range.push_back(10.0);
      grid.linked.push_back(all_one_run || u(rng) > 0.05f ? links[static_cast<std::size_t>(u(rng) * 6.0f)] : 0);
      grid.index.push_back(static_cast<std::uint32_t>(grid.index.size()));
    }
    const bool closed = ring % 3 != 1;
    if (!closed && sizes[ring] > 0) grid.linked[grid.ring_begin.back()] = 0;  // as the grid leaves an open ring
    grid.ring_closed.push_back(closed ? 1 : 0);
    grid.ring_begin.push_back(static_cast<std::uint32_t>(grid.index.size()));
  }
  grid.num_rings = rings;
  {
    // ring 9 (closed): a run that starts at its last sample and goes on across the seam
    const std::uint32_t b = grid.ring_begin[9], K = grid.ring_begin[10] - b;
    const float turn[5] = {0.1f, 0.7f, 0.9f, 0.8f, 0.1f};  // samples K - 2, K - 1, 0, 1, 2
    const std::uint32_t at[5] = {K - 2, K - 1, 0, 1, 2};
    for (int j = 0; j < 5; ++j)
    {
      f.turning[b + at[j]] = turn[j];
      f.smoothness[b + at[j]] = f.discontinuity[b + at[j]] = 0.0f;
      grid.linked[b + at[j]] = 1;
    }
  }
  out.rings = rings;
  return out;
}

// Runs met while writing out the rule, and of them those across the seam and those keeping an Edge
struct RunCounts
{
  std::size_t runs = 0, seam_runs = 0, kept = 0;
};

// Ring `ring`'s labels after non-max suppression, from its labels without (`raw`) by the rule
// written out run by run
std::vector<Label> suppressedByRuns(const ScanGrid& grid, const Features& f, const std::vector<Label>& raw, int ring,
                                    RunCounts& n)
{
  const std::uint32_t b = grid.ring_begin[ring], K = grid.ring_begin[ring + 1] - b;
  const bool closed = grid.ring_closed[ring] != 0;
  auto feature = [&](std::uint32_t k) { return raw[b + k] == Label::Edge || raw[b + k] == Label::Corner; };
  // k continues the run of the sample before it (k - 1, or K - 1 for k = 0 on a closed ring)
  auto continues = [&](std::uint32_t k) { return feature(k) && grid.linked[b + k] != 0 && (closed || k != 0); };
  std::vector<Label> want(raw.begin() + b, raw.begin() + b + K);
  std::uint32_t s = 0;
  while (s < K && continues(s)) ++s;
  for (std::uint32_t i = 0; s < K && i < K;)
  {
    const std::uint32_t k0 = (s + i) % K;
    if (!feature(k0))
    {
      ++i;
      continue;
    }
    std::uint32_t len = 1;
    while (i + len < K && continues((s + i + len) % K)) ++len;
    bool corner = false;
    std::uint32_t peak = K;
    float best = -1.0f;
    for (std::uint32_t j = 0; j < len; ++j)
    {
      const std::uint32_t k = (s + i + j) % K;
      corner |= raw[b + k] == Label::Corner;
      if (raw[b + k] == Label::Edge && f.turning[b + k] > best)
      {
        best = f.turning[b + k];
        peak = k;
      }
    }
    for (std::uint32_t j = 0; j < len; ++j)
    {
      const std::uint32_t k = (s + i + j) % K;
      if (raw[b + k] == Label::Edge && (corner || k != peak)) want[k] = Label::Plane;
    }
    ++n.runs;
    n.seam_runs += len > 1 && (s + i) % K + len > K ? 1 : 0;
    n.kept += !corner && peak < K ? 1 : 0;
    i += len;
  }
  return want;
}
}  // namespace

// Non-maximum suppression against the rule written out run by run: of each run of linked Edges
// and Corners (followed across the seam of a closed ring), a run touching a Corner keeps no Edge,
// any other keeps its first largest turning angle. Rings open and closed, of 0 to 700 samples,
// with runs of one to 19 samples, gaps (links of any non-zero byte), runs across the seam (one
// starting at the last sample) and a ring that is one run: the search skips runs of one sample
// eight labels at a time.
TEST(Classifier, NonMaxSuppressionKeepsEachRunsPeak)
{
  const RunRings in = runRings();
  const ScanGrid& grid = in.grid;
  const Features& f = in.f;
  const int rings = in.rings;
  RingThresholds t;
  t.curvature_high = t.curvature_low = 0.5f;
  t.smoothness_high = 0.5f;
  t.discontinuity_high = t.discontinuity_low = 0.5f;
  const std::vector<RingThresholds> thr(static_cast<std::size_t>(rings), t);
  Params P;
  P.non_max_suppression = false;
  Classifier c;
  std::vector<Label> raw, labels;
  c.classify(grid, f, P, thr, raw);
  P.non_max_suppression = true;
  c.classify(grid, f, P, thr, labels);
  RunCounts n;
  for (int ring = 0; ring < rings; ++ring)
  {
    const std::uint32_t b = grid.ring_begin[ring], K = grid.ring_begin[ring + 1] - b;
    const std::vector<Label> want = suppressedByRuns(grid, f, raw, ring, n);
    for (std::uint32_t k = 0; k < K; ++k)
      ASSERT_EQ(static_cast<int>(labels[b + k]), static_cast<int>(want[k])) << "ring " << ring << " sample " << k;
  }
  EXPECT_GT(n.runs, 150u);
  EXPECT_GT(n.seam_runs, 1u);
  EXPECT_GT(n.kept, 50u);
}
