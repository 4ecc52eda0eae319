// Issue 30 (item 1): LOAM's rules that keep points out of every feature set
// (loam/loam_selector.cpp), on ray-cast scenes whose answer is known: the occluded side of depth
// jumps and surfaces along the beam, each with the rule off as a control.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>
#include <vector>
#include "ring_curvature/pipeline.hpp"
#include "../support/loam_run.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{

TEST(LoamFeatures, OccludedSideOfDepthJumpsIsInNoSet)
{
  RayScene s;
  s.boxes.push_back({20.0, 0.0, -1.8, 6.0, 0.5, 15.0, 0.0});  // far wall, facing the sensor
  s.boxes.push_back({8.0, 0.0, -1.8, 1.5, 0.5, 1.0, 0.0});    // box in front of it
  const int front = 2, far = 1;
  Params P = baseParams();
  P.loam_less_flat_voxel = 0.0f;  // every eligible Plane point is less flat
  LoamRun run(s, P);
  checkSets(run.pipe, run.loam, P);
  const ScanGrid& g = run.grid();
  const std::vector<Label>& labels = run.pipe.gridLabels();
  const std::set<std::uint32_t> in = allSets(run.loam);
  const std::set<std::uint32_t> sharp(run.loam.sharp.begin(), run.loam.sharp.end());

  // Far-side samples next to each jump: the first loam_suppression + 1 on the far surface.
  std::vector<std::uint32_t> shadow;
  int jumps = 0, near_corner_sharp = 0;
  for (std::uint32_t p = 0; p < g.size(); ++p)
  {
    const std::int64_t q = walk(g, p, -1, 1);
    if (q < 0) continue;
    const Hit &a = run.hit(static_cast<std::uint32_t>(q)), &b = run.hit(p);
    if (a.object < 0 || b.object < 0 || a.object == b.object) continue;
    if (std::fabs(a.t - b.t) < 0.2 * std::min(a.t, b.t)) continue;
    if (!((a.object == front && b.object == far) || (a.object == far && b.object == front))) continue;
    ++jumps;
    const bool far_after = b.t > a.t;
    const std::uint32_t far_pos = far_after ? p : static_cast<std::uint32_t>(q);
    const std::uint32_t near_pos = far_after ? static_cast<std::uint32_t>(q) : p;
    for (int i = 0; i <= P.loam_suppression; ++i)
    {
      const std::int64_t r = walk(g, far_pos, far_after ? 1 : -1, i);
      if (r < 0 || run.hit(static_cast<std::uint32_t>(r)).object != far) break;
      shadow.push_back(static_cast<std::uint32_t>(r));
    }
    for (int i = 0; i <= 1; ++i)  // the near side's sample at the jump, or the next one
    {
      const std::int64_t r = walk(g, near_pos, far_after ? -1 : 1, i);
      if (r >= 0 && labels[static_cast<std::size_t>(r)] == Label::Corner && sharp.count(static_cast<std::uint32_t>(r)))
      {
        ++near_corner_sharp;
        break;
      }
    }
  }
  std::size_t shadow_plane = 0;
  for (const std::uint32_t p : shadow)
  {
    shadow_plane += labels[p] == Label::Plane;
    EXPECT_FALSE(in.count(p)) << "far-side position " << p << " (ring " << g.ringOf(p) << ", " << labelName(labels[p])
                              << ") next to a depth jump is in a LOAM set";
  }
  std::printf("occlusion: %d jumps, %zu far-side samples (%zu Plane), %d with a sharp near-side Corner\n", jumps,
              shadow.size(), shadow_plane, near_corner_sharp);
  EXPECT_GE(jumps, 16);                  // both sides of the front box on the rings that see it
  EXPECT_GT(near_corner_sharp, 0);       // the occluder's own edge is a landmark
  EXPECT_GT(shadow_plane, 0u);           // else the exclusion is not what keeps them out

  // Control: with the occlusion rule off, far-side Plane samples do enter the less flat set.
  P.loam_occlusion_ratio = 10.0f;
  const LoamFeatures off = run.reselect(P);
  const std::set<std::uint32_t> in_off = allSets(off);
  std::size_t leaked = 0;
  for (const std::uint32_t p : shadow) leaked += in_off.count(p);
  EXPECT_GT(leaked, 0u);
}

/// A wall along x at y = 3 (60 m long, 11.8 m high) seen from beside its near end: far along it
/// the beam meets it at grazing incidence. Splits its samples into grazing ones with both ring
/// neighbours linked, grazing ones at a gap (the wall's far end or top: no return beyond), and
/// ones seen squarely.
struct GrazingWall
{
  LoamRun run;
  std::vector<std::uint32_t> inner, at_gap;
  std::size_t steep = 0, steep_in = 0;
  explicit GrazingWall(const Params& P) : run(scene(), P)
  {
    const ScanGrid& g = run.grid();
    const std::set<std::uint32_t> in = allSets(run.loam);
    const double step = 0.2 * kDeg;
    for (std::uint32_t p = 0; p < g.size(); ++p)
    {
      if (run.hit(p).object != 1) continue;
      const double th = std::atan2(std::fabs(g.y[p]), g.x[p]);  // azimuth from the wall's direction
      if (th <= 0) continue;
      const double rel = step / std::tan(th);  // range step / range between ring neighbours
      if (rel > 0.03)                          // well above loam_parallel_ratio
        (walk(g, p, -1, 1) >= 0 && walk(g, p, 1, 1) >= 0 ? inner : at_gap).push_back(p);
      else if (rel < 0.01)
      {
        ++steep;
        steep_in += in.count(p);
      }
    }
  }
  static RayScene scene()
  {
    RayScene s;
    s.boxes.push_back({30.0, 3.1, -1.8, 10.0, 30.0, 0.1, 0.0});
    return s;
  }
};

TEST(LoamFeatures, SurfaceAlongTheBeamGivesNoFeatures)
{
  Params P = baseParams();
  P.loam_less_flat_voxel = 0.0f;
  GrazingWall w(P);
  checkSets(w.run.pipe, w.run.loam, P);
  const std::set<std::uint32_t> in = allSets(w.run.loam);
  for (const std::uint32_t p : w.inner)
    EXPECT_FALSE(in.count(p)) << "position " << p << " on the wall along the beam ("
                              << labelName(w.run.pipe.gridLabels()[p]) << ") is in a LOAM set";
  std::printf("grazing wall: %zu samples along the beam (%zu more at a gap), %zu of %zu steep ones in a set\n",
              w.inner.size(), w.at_gap.size(), w.steep_in, w.steep);
  EXPECT_GT(w.inner.size(), 100u);
  EXPECT_GT(w.steep_in, w.steep / 4);  // the same wall seen squarely does give features

  // Control: with the rule off, grazing samples enter the sets.
  P.loam_parallel_ratio = 10.0f;
  const LoamFeatures off = w.run.reselect(P);
  const std::set<std::uint32_t> in_off = allSets(off);
  std::size_t leaked = 0;
  for (const std::uint32_t p : w.inner) leaked += in_off.count(p);
  std::printf("grazing wall, rule off: %zu of %zu grazing samples in a set\n", leaked, w.inner.size());
  EXPECT_GT(leaked, 0u);
}

// The last grazing sample before a gap (no return beyond the wall's far end or top) has one ring
// neighbour only: the steep step to it must suffice.
TEST(LoamFeatures, SurfaceAlongTheBeamAtAGapGivesNoFeatures)
{
  Params P = baseParams();
  P.loam_less_flat_voxel = 0.0f;
  GrazingWall w(P);
  const std::set<std::uint32_t> in = allSets(w.run.loam);
  const std::set<std::uint32_t> less_flat(w.run.loam.less_flat.begin(), w.run.loam.less_flat.end());
  std::size_t kept = 0;
  for (const std::uint32_t p : w.at_gap)
    if (in.count(p))
    {
      ++kept;
      std::printf("grazing sample at a gap in a set: position %u ring %d (%.2f %.2f %.2f) %s%s\n", p,
                  w.run.grid().ringOf(p), w.run.grid().x[p], w.run.grid().y[p], w.run.grid().z[p],
                  labelName(w.run.pipe.gridLabels()[p]), less_flat.count(p) ? ", less flat" : "");
    }
  std::printf("grazing wall: %zu of %zu samples at a gap in a set\n", kept, w.at_gap.size());
  EXPECT_GT(w.at_gap.size(), 0u);
  EXPECT_EQ(kept, 0u) << "grazing samples next to a gap in a LOAM set";
}

}  // namespace
