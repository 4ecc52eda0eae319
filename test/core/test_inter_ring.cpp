// The inter-ring steps (classification/inter_ring.cpp) on a scene whose answer is known: a room
// of walls, a "hedge" of random depth in front of part of it, and a pole in front of another
// part, on 16 rings. Each step is checked with its switch on and off, so that a step that does
// nothing (or the wrong thing) fails.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "../support/synthetic_cloud.hpp"
#include "ring_curvature/pipeline.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
constexpr double kPi = 3.14159265358979323846;
enum Part : int { kWall = 0, kHedge = 1, kPole = 2, kShadow = 3 };

struct Scene
{
  SyntheticCloud cloud;
  std::vector<int> part;
};

Scene makeScene()
{
  Scene s;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> depth(0.0, 1.0);
  const double step = 0.2 * kPi / 180;
  for (int n = 0; n < 16; ++n)
  {
    const double phi = (-15 + 2 * n) * kPi / 180;
    for (int k = 0; k < 1800; ++k)
    {
      const double th = -kPi + k * step;
      double dx, dy, dz;
      beamDir(phi, th, dx, dy, dz);
      double t = 10.0 / std::max(0.2, std::fabs(std::cos(th)));  // walls
      int part = kWall;
      if (std::fabs(th) < 0.3)  // the hedge, 1 m deep
      {
        t = 8.0 + depth(rng);
        part = kHedge;
      }
      const double pole = th - 2.5;  // a pole 0.2 m wide at 6 m in front of the wall behind it
      if (std::fabs(pole) < 0.1 / 6.0)
      {
        t = 6.0;
        part = kPole;
      }
      else if (std::fabs(pole) < 0.1 / 6.0 + 1.5 * step)
        part = kShadow;  // the wall right beside the pole: the far side of its depth jumps
      s.cloud.add(t * dx, t * dy, t * dz, n);
      s.part.push_back(part);
    }
  }
  return s;
}

// Share of the points of `part` labelled `l` (or `also`).
double share(const Scene& s, const FrameResult& r, int part, Label l, Label also = Label::None)
{
  std::size_t n = 0, hit = 0;
  for (std::size_t i = 0; i < s.part.size(); ++i)
    if (s.part[i] == part)
    {
      ++n;
      const auto got = static_cast<Label>(r.label[i]);
      hit += got == l || (also != Label::None && got == also) ? 1 : 0;
    }
  return n ? static_cast<double>(hit) / static_cast<double>(n) : 0.0;
}

FrameResult run(const Scene& s, const Params& p)
{
  Pipeline pipe(p);
  FrameResult r;
  EXPECT_TRUE(pipe.process(s.cloud.view(), r).ok);
  return r;
}

Params allOff()
{
  Params p;
  p.inter_ring_roughness = p.suppress_foliage_features = p.occlusion_aware_jumps = p.thin_objects = false;
  return p;
}
}  // namespace

TEST(InterRing, RoughnessAcrossRingsMakesTheHedgeRoughAndLeavesTheWalls)
{
  const Scene s = makeScene();
  Params on = allOff();
  on.inter_ring_roughness = true;
  on.rough_smoothness_min = 1e-3f;  // (the hedge's scatter is 0.3 m, the walls' none)
  on.rough_vertical_min = 0.05f;
  const FrameResult r = run(s, on);
  EXPECT_GT(share(s, r, kHedge, Label::Rough), 0.8);
  EXPECT_GT(share(s, r, kWall, Label::Plane), 0.95);
  // (a threshold no point reaches: the window never calls anything Rough)
  on.rough_vertical_min = 100.0f;
  EXPECT_LT(share(s, run(s, on), kHedge, Label::Rough), 0.05);
}

TEST(InterRing, ThinStackedRunsInFrontOfBothNeighboursAreEdges)
{
  // The pole's ends stay Corners (the near side of its jumps); its other points become Edges on
  // the rings with two rings above and below (thin_min_stack 4 of 4): 12 of the 16.
  const Scene s = makeScene();
  Params on = allOff();
  on.thin_objects = true;
  const double off_edges = share(s, run(s, allOff()), kPole, Label::Edge);
  const FrameResult with = run(s, on);
  const double on_edges = share(s, with, kPole, Label::Edge);
  std::printf("pole points Edge: %.3f without, %.3f with the thin-object step (Edge or Corner: %.3f)\n", off_edges,
              on_edges, share(s, with, kPole, Label::Edge, Label::Corner));
  EXPECT_GT(on_edges, 0.5);
  EXPECT_GT(on_edges, off_edges + 0.4);
  EXPECT_GT(share(s, with, kPole, Label::Edge, Label::Corner), 0.7);
  on.thin_max_width = 0.1f;  // narrower than the pole: not thin
  EXPECT_LT(share(s, run(s, on), kPole, Label::Edge), off_edges + 0.05);
}

TEST(InterRing, OnlyTheNearSideOfAJumpIsACorner)
{
  const Scene s = makeScene();
  Params on = allOff();
  on.occlusion_aware_jumps = true;
  const double off_share = share(s, run(s, allOff()), kShadow, Label::Corner);
  EXPECT_GE(off_share, 0.4);  // ring-wise, the wall right beside the pole is a jump's Corner
  EXPECT_EQ(share(s, run(s, on), kShadow, Label::Corner), 0.0);
}

TEST(InterRing, QuartileModeIsThePapersWhateverTheSwitches)
{
  const Scene s = makeScene();
  Params a = allOff(), b;
  a.classifier_mode = b.classifier_mode = ClassifierMode::Quartile;
  b.inter_ring_roughness = b.suppress_foliage_features = b.occlusion_aware_jumps = b.thin_objects = true;
  EXPECT_EQ(run(s, a).label, run(s, b).label);
}
