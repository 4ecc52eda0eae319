// Thresholds: O(K) selection, Algorithm 1 proportions, and the robust mode on clean geometry.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "../support/ray_scene.hpp"
#include "ring_curvature/pipeline.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

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
