// The PCL baselines label a known scene the way their documented rules say they should.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "baselines/euclidean_clustering.hpp"
#include "baselines/pca_curvature.hpp"
#include "synthetic_scene.hpp"

namespace rc = ring_curvature;
namespace rt = ring_curvature::test;

namespace
{
constexpr std::uint8_t kNone = 0, kPlane = 1, kEdge = 2, kRough = 4;

rt::SyntheticFrame scene(bool organized = false)
{
  rt::SceneOptions o;
  o.range_noise = 0.0f;
  o.organized = organized;
  return rt::makeScene(o);
}

double fraction(const std::vector<std::uint8_t>& labels, const std::vector<rt::Surface>& surface,
                rt::Surface s, std::uint8_t label)
{
  std::size_t n = 0, hit = 0;
  for (std::size_t i = 0; i < labels.size(); ++i)
    if (surface[i] == s)
    {
      ++n;
      hit += labels[i] == label;
    }
  return n == 0 ? 0.0 : static_cast<double>(hit) / static_cast<double>(n);
}
}  // namespace

TEST(PcaCurvature, FlatGroundIsPlaneAndCurvatureIsPclSigma)
{
  const auto f = scene();
  rc::baselines::PcaCurvature pca;
  std::vector<std::uint8_t> labels;
  pca.label(f.view, labels);
  ASSERT_EQ(labels.size(), f.view.size());
  EXPECT_GT(fraction(labels, f.surface, rt::kGround, kPlane), 0.9);
  // sigma = l0 / (l0 + l1 + l2) lies in [0, 1/3] for every labelled point.
  for (std::size_t i = 0; i < labels.size(); ++i)
  {
    const float s = pca.curvature()[i];
    ASSERT_TRUE(std::isfinite(s));
    ASSERT_GE(s, 0.0f);
    ASSERT_LE(s, 1.0f / 3.0f + 1e-5f);
    const std::uint8_t expect = s < 0.02f ? kPlane : (s < 0.10f ? kEdge : kRough);
    ASSERT_EQ(labels[i], expect) << "point " << i << " sigma " << s;
  }
}

TEST(PcaCurvature, InvalidReturnsAreNone)
{
  const auto f = scene(true);  // organized, NaN where a ray missed
  rc::baselines::PcaCurvature pca;
  std::vector<std::uint8_t> labels;
  pca.label(f.view, labels);
  ASSERT_EQ(labels.size(), f.view.size());
  std::size_t misses = 0;
  for (std::size_t i = 0; i < labels.size(); ++i)
    if (f.surface[i] == rt::kMiss)
    {
      ++misses;
      EXPECT_EQ(labels[i], kNone);
    }
  EXPECT_GT(misses, 0u);
}

TEST(EuclideanClustering, SizeRuleOnKnownClusters)
{
  const auto f = scene();
  rc::baselines::EuclideanClustering ec;
  std::vector<std::uint8_t> labels;
  ec.label(f.view, labels);
  ASSERT_EQ(labels.size(), f.view.size());
  // Ground, walls and the boxes standing on the ground touch: one large cluster -> Plane.
  EXPECT_EQ(fraction(labels, f.surface, rt::kGround, kPlane), 1.0);
  EXPECT_EQ(fraction(labels, f.surface, rt::kWall, kPlane), 1.0);
  // The floating sign is its own mid-sized cluster -> Edge, all of it in one cluster.
  EXPECT_EQ(fraction(labels, f.surface, rt::kSign, kEdge), 1.0);
  std::int32_t sign_cluster = -2;
  for (std::size_t i = 0; i < labels.size(); ++i)
    if (f.surface[i] == rt::kSign)
    {
      if (sign_cluster == -2)
        sign_cluster = ec.cluster()[i];
      EXPECT_EQ(ec.cluster()[i], sign_cluster);
    }
  EXPECT_GE(ec.numClusters(), 2u);
}

TEST(EuclideanClustering, ThresholdsMoveLabels)
{
  rc::baselines::EuclideanClusteringParams p;
  p.plane_min_points = 1000000;  // no cluster is large...
  p.small_max_points = 100000;   // ...and every one is small
  rc::baselines::EuclideanClustering ec(p);
  const auto f = scene();
  std::vector<std::uint8_t> labels;
  ec.label(f.view, labels);
  EXPECT_EQ(fraction(labels, f.surface, rt::kGround, kRough), 1.0);
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
