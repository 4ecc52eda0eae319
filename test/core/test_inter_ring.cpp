// The inter-ring steps (classification/inter_ring.cpp) on a scene whose answer is known: a room
// of walls, a "hedge" of random depth in front of part of it with a pole in front of the hedge,
// a pole in front of a wall, a pole partly behind another, a vertical crease (a room's corner)
// and a dent on one ring only, on 16 rings. Each step is checked with its switch on and off, so that a step that does
// nothing (or the wrong thing) fails.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include "../support/synthetic_cloud.hpp"
#include "ring_curvature/pipeline.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
constexpr double kPi = 3.14159265358979323846;
enum Part : int { kWall = 0, kHedge = 1, kPole = 2, kShadow = 3, kHidden = 4, kHedgePole = 5, kCrease = 6, kDent = 7, kStrip = 8 };
constexpr int kDentRing = 8;
constexpr std::size_t kColumns = 1800;  // samples per ring, rings one after the other

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
    for (std::size_t k = 0; k < kColumns; ++k)
    {
      const double th = -kPi + static_cast<double>(k) * step;
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
      // a pole 0.2 m wide at 6 m, and beside it a second at 7 m whose left third it hides
      const double front = th + 2.5, hidden = th + 2.5 - (0.1 / 6.0 + 0.005);
      if (std::fabs(front) < 0.1 / 6.0)
        t = 6.0;
      else if (std::fabs(hidden) < 0.1 / 7.0)
      {
        t = 7.0;
        part = kHidden;
      }
      if (std::fabs(th - 0.15) < 0.1 / 6.0)  // a pole at 6 m in front of the hedge
      {
        t = 6.0;
        part = kHedgePole;
      }
      if (th > 1.0 && th < 1.4)  // a room's corner: two walls that meet at 7 m, at azimuth 1.2
      {
        const double alpha = th < 1.2 ? 0.6 : 1.8;
        t = 7.0 * std::cos(0.6) / (std::cos(phi) * std::cos(th - alpha));
        part = std::fabs(th - 1.2) < 1.5 * step ? kCrease : kWall;
      }
      if ((n == 7 || n == 8) && th > -1.0 && th < -0.8)  // a rough strip two rings tall on the wall
      {
        t += depth(rng) - 0.5;
        part = kStrip;
      }
      if (n == kDentRing && std::fabs(th - 0.6) < 4.5 * step)  // a dent, 15 cm deep, on one ring only
      {
        t += 0.15 * (1.0 - std::fabs(th - 0.6) / (4.5 * step));
        part = kDent;
      }
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
  p.inter_ring_roughness = p.edge_vertical_support = p.suppress_foliage_features = p.occlusion_aware_jumps =
      p.thin_objects = false;
  return p;
}

// Only the rough window, with bounds well above the walls' scatter (none) and below the hedge's
// (0.3 m).
Params roughWindowOn()
{
  Params p = allOff();
  p.inter_ring_roughness = true;
  p.rough_smoothness_min = 1e-3f;
  p.rough_vertical_min = 0.05f;
  return p;
}
}  // namespace

TEST(InterRing, RoughnessAcrossRingsMakesTheHedgeRoughAndLeavesTheWalls)
{
  const Scene s = makeScene();
  Params on = roughWindowOn();
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
  const FrameResult r = run(s, on);
  EXPECT_EQ(share(s, r, kShadow, Label::Corner), 0.0);
  // the Corner moves to the near side: on every ring, both of the pole's outlines are Corners
  for (int n = 0; n < 16; ++n)
  {
    int corners = 0;
    for (std::size_t i = 0; i < s.part.size(); ++i)
      corners += static_cast<int>(i / kColumns) == n && s.part[i] == kPole && r.label[i] == static_cast<std::uint8_t>(Label::Corner);
    EXPECT_EQ(corners, 2) << "ring " << n;
  }
}

TEST(InterRing, APolePartlyHiddenByAnotherIsThinToo)
{
  const Scene s = makeScene();
  Params on = allOff();
  on.thin_objects = true;
  on.thin_occluded = false;
  const double alone = share(s, run(s, on), kHidden, Label::Edge, Label::Corner);
  on.thin_occluded = true;
  const double with = share(s, run(s, on), kHidden, Label::Edge, Label::Corner);
  std::printf("hidden pole Edge/Corner: %.3f in front of both sides only, %.3f with thin_occluded\n", alone, with);
  EXPECT_GT(with, 0.6);
  EXPECT_GT(with, alone + 0.4);
}

TEST(InterRing, AnEdgeNeedsSupportFromTheRingAboveOrBelow)
{
  const Scene s = makeScene();
  Params on = allOff();
  const FrameResult off = run(s, on);
  on.edge_vertical_support = true;
  const FrameResult with = run(s, on);
  // the dent on one ring is an Edge ring-wise, and not with support; the corner keeps its Edges
  ASSERT_GT(share(s, off, kDent, Label::Edge), 0.0);
  EXPECT_EQ(share(s, with, kDent, Label::Edge), 0.0);
  const double crease_off = share(s, off, kCrease, Label::Edge), crease_on = share(s, with, kCrease, Label::Edge);
  std::printf("room corner Edge: %.3f ring-wise, %.3f with vertical support\n", crease_off, crease_on);
  EXPECT_GT(crease_off, 0.3);
  EXPECT_GE(crease_on, crease_off - 0.02);
}

TEST(InterRing, AnOutlineStackedOverRingsSurvivesFoliageSuppression)
{
  // the pole in front of the hedge: its outlines are Corners in a rough window; suppression
  // makes them Rough unless they are a silhouette stacked over rings (thin objects off here)
  const Scene s = makeScene();
  Params on = roughWindowOn();
  on.suppress_foliage_features = true;
  on.foliage_keep_silhouettes = false;
  const double dropped = share(s, run(s, on), kHedgePole, Label::Corner, Label::Edge);
  on.foliage_keep_silhouettes = true;
  const double kept = share(s, run(s, on), kHedgePole, Label::Corner, Label::Edge);
  std::printf("pole in front of the hedge, Edge/Corner: %.3f suppressed, %.3f keeping silhouettes\n", dropped, kept);
  // (the pole is ~10 samples wide: its two outlines on every ring are 0.2 of its points)
  EXPECT_LT(dropped, 0.1);
  EXPECT_GT(kept, 0.15);
  EXPECT_GT(kept, dropped + 0.1);
}

TEST(InterRing, TheRoughWindowSpansTheRingsAsConfigured)
{
  // a rough strip two rings tall: 2 of a 3-ring window's rings are rough, 2 of a 5-ring one's
  const Scene s = makeScene();
  Params on = roughWindowOn();
  on.rough_window_rings = 1;
  const double three = share(s, run(s, on), kStrip, Label::Rough);
  on.rough_window_rings = 2;
  const double five = share(s, run(s, on), kStrip, Label::Rough);
  std::printf("strip points Rough: %.3f with a 3-ring window, %.3f with a 5-ring one\n", three, five);
  EXPECT_GT(three, 0.5);
  EXPECT_LT(five, 0.1);
}

TEST(InterRing, APoleIsOnePrimitiveAlongItsAxis)
{
  // the thin-object step's Edges over the pole's rings join into one edge chain whose axis is the
  // pole's (vertical), as a SLAM front end or rviz user expects of a pole
  const Scene s = makeScene();
  Params on = allOff();
  on.thin_objects = true;
  const FrameResult r = run(s, on);
  std::map<std::int32_t, int> count;
  int edges = 0;
  for (std::size_t i = 0; i < s.part.size(); ++i)
    if (s.part[i] == kPole && r.label[i] == static_cast<std::uint8_t>(Label::Edge))
    {
      ++edges;
      ++count[r.primitive[i]];
    }
  ASSERT_GT(edges, 20);
  const auto best = std::max_element(count.begin(), count.end(),
                                     [](const auto& a, const auto& b) { return a.second < b.second; });
  ASSERT_GE(best->first, 0);
  EXPECT_GE(best->second, 0.9 * edges);
  const PrimitiveInfo& prim = r.primitives.primitives[static_cast<std::size_t>(best->first)];
  EXPECT_EQ(prim.label, Label::Edge);
  EXPECT_GT(std::fabs(prim.axis.z()), 0.95f);
  EXPECT_GE(prim.ring_max - prim.ring_min, 10);
}

TEST(InterRing, QuartileModeIsThePapersWhateverTheSwitches)
{
  const Scene s = makeScene();
  Params a = allOff(), b;
  a.classifier_mode = b.classifier_mode = ClassifierMode::Quartile;
  b.inter_ring_roughness = b.edge_vertical_support = b.suppress_foliage_features = b.occlusion_aware_jumps =
      b.thin_objects = true;
  EXPECT_EQ(run(s, a).label, run(s, b).label);
}
