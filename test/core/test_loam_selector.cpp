// Issue 30 (item 1): LOAM's feature sets (loam/loam_selector.cpp) on ray-cast scenes whose answer
// is known: quotas per ring and sector, LOAM's rules (neighbour suppression, occluded side of depth
// jumps, surfaces along the beam), the less flat voxel grid and the sweep times.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>
#include "loam/degeneracy.hpp"
#include "ring_curvature/pipeline.hpp"
#include "../support/loam_run.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{

// --- 1. quotas and order ----------------------------------------------------------------------

TEST(LoamFeatures, QuotasAndOrderOnBoxScene)
{
  const Params P = baseParams();
  LoamRun run(boxScene(), P);
  const MaxCounts d = checkSets(run.pipe, run.loam, P);
  std::printf("box scene, default quotas: sharp %zu, less sharp %zu, flat %zu, less flat %zu; max per sector %d/%d/%d\n",
              run.loam.sharp.size(), run.loam.less_sharp.size(), run.loam.flat.size(), run.loam.less_flat.size(), d.sharp,
              d.less_sharp, d.flat);
  // Enough of everything that the quotas bind somewhere.
  EXPECT_EQ(d.sharp, P.loam_sharp_per_sector);
  EXPECT_EQ(d.flat, P.loam_flat_per_sector);
  EXPECT_GT(run.loam.less_sharp.size(), run.loam.sharp.size());
  EXPECT_GT(run.loam.less_flat.size(), run.loam.flat.size());

  // Tighter quotas: the counts follow.
  Params t = P;
  t.loam_sharp_per_sector = 1;
  t.loam_less_sharp_per_sector = 2;
  t.loam_flat_per_sector = 2;
  const LoamFeatures lt = run.reselect(t);
  const MaxCounts mt = checkSets(run.pipe, lt, t);
  EXPECT_EQ(mt.sharp, 1);
  EXPECT_EQ(mt.less_sharp, 2);
  EXPECT_EQ(mt.flat, 2);
  EXPECT_LT(lt.sharp.size(), run.loam.sharp.size());
  EXPECT_LT(lt.less_sharp.size(), run.loam.less_sharp.size());
  EXPECT_LT(lt.flat.size(), run.loam.flat.size());

  // Looser: more.
  Params w = P;
  w.loam_sharp_per_sector = 4;
  w.loam_flat_per_sector = 8;
  const LoamFeatures lw = run.reselect(w);
  const MaxCounts mw = checkSets(run.pipe, lw, w);
  EXPECT_EQ(mw.flat, 8);
  EXPECT_GT(lw.sharp.size(), run.loam.sharp.size());
  EXPECT_GT(lw.flat.size(), run.loam.flat.size());

  // One sector per ring: at most the quota per ring.
  Params one = P;
  one.loam_sectors = 1;
  const LoamFeatures l1 = run.reselect(one);
  checkSets(run.pipe, l1, one);
  EXPECT_LE(l1.flat.size(), static_cast<std::size_t>(one.loam_flat_per_sector * run.grid().num_rings));
  EXPECT_LE(l1.sharp.size(), static_cast<std::size_t>(one.loam_sharp_per_sector * run.grid().num_rings));

  // Quotas 0: no sharp, less sharp or flat points; the less flat set is the voxel grid's.
  Params z = P;
  z.loam_sharp_per_sector = 0;
  z.loam_less_sharp_per_sector = 0;
  z.loam_flat_per_sector = 0;
  const LoamFeatures l0 = run.reselect(z);
  checkSets(run.pipe, l0, z);
  EXPECT_TRUE(l0.sharp.empty());
  EXPECT_TRUE(l0.less_sharp.empty());
  EXPECT_TRUE(l0.flat.empty());
  EXPECT_FALSE(l0.less_flat.empty());
}

TEST(LoamFeatures, SharpEqualsLessSharpWhenTheQuotasMatch)
{
  Params P = baseParams();
  P.loam_sharp_per_sector = 3;
  P.loam_less_sharp_per_sector = 3;
  LoamRun run(boxScene(), P);
  checkSets(run.pipe, run.loam, P);
  EXPECT_FALSE(run.loam.sharp.empty());
  EXPECT_EQ(run.loam.sharp, run.loam.less_sharp);
}

TEST(LoamFeatures, NoRoughPointInAnySet)
{
  // A hedge of random depth in front of a wall: Rough points, which must not become features.
  RayScene s;
  s.boxes.push_back({12.0, 0.0, -1.8, 4.0, 0.2, 12.0, 0.0});
  // add the hedge by perturbing a scan: random range over a sector
  ScannedFrame f = scan(s, vlp16());
  SyntheticCloud c;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> depth(0.0, 1.0);
  for (std::size_t i = 0; i < f.cloud.size(); ++i)
  {
    const double th = f.column[i] * 0.2 * kDeg;
    double dx, dy, dz;
    beamDir(vlp16().elevations[static_cast<std::size_t>(f.ring[i])], th, dx, dy, dz);
    double t = f.hits[i].t;
    if (std::fabs(th - kPi / 2) < 0.4 && f.ring[i] >= 6) t = 8.0 + depth(rng);  // the hedge
    if (std::isfinite(t) && t < 200)
      c.add(t * dx, t * dy, t * dz, f.ring[i]);
    else
      c.addNaN(f.ring[i]);
  }
  const Params P = baseParams();
  Pipeline pipe(P);
  FrameResult r;
  ASSERT_TRUE(pipe.process(c.view(), r).ok);
  LoamFeatures L;
  pipe.selectLoamFeatures(c.view(), L);
  std::size_t rough = 0;
  for (const Label l : pipe.gridLabels()) rough += l == Label::Rough;
  std::printf("hedge: %zu Rough points\n", rough);
  EXPECT_GT(rough, 300u);  // else the test says nothing
  checkSets(pipe, L, P);
}

// --- 2. neighbour suppression -----------------------------------------------------------------

void checkSuppression(const LoamRun& run, const LoamFeatures& L, int suppression)
{
  const ScanGrid& g = run.grid();
  // The points odometry matches block their neighbours: a sharp point keeps every later pick
  // (less sharp or flat) out of its `suppression` linked samples, and a flat one the other flat
  // ones. Less sharp points beyond the sharp ones block nothing (every Edge/Corner is a landmark).
  const std::set<std::uint32_t> sharp(L.sharp.begin(), L.sharp.end()), flat(L.flat.begin(), L.flat.end());
  std::set<std::uint32_t> later(L.less_sharp.begin(), L.less_sharp.end());
  later.insert(L.flat.begin(), L.flat.end());
  int pairs = 0;
  const auto check = [&](const std::set<std::uint32_t>& from, const std::set<std::uint32_t>& others, const char* what) {
    for (const std::uint32_t p : from)
      for (int dir = -1; dir <= 1; dir += 2)
        for (int i = 1; i <= suppression; ++i)
        {
          const std::int64_t q = walk(g, p, dir, i);
          if (q < 0) break;
          if (others.count(static_cast<std::uint32_t>(q)))
          {
            ++pairs;
            ADD_FAILURE() << what << ": positions " << p << " and " << q << " (ring " << g.ringOf(p) << ") are " << i
                          << " linked samples apart, suppression " << suppression;
          }
        }
  };
  check(sharp, later, "sharp next to a later pick");
  check(flat, flat, "two flat points");
  EXPECT_EQ(pairs, 0);
}

TEST(LoamFeatures, NeighbourSuppression)
{
  Params P = baseParams();
  LoamRun run(boxScene(), P);
  ASSERT_FALSE(run.loam.less_sharp.empty());
  checkSuppression(run, run.loam, P.loam_suppression);

  // A wider suppression spreads the picks; generous quotas so that it is what limits them.
  P.loam_suppression = 12;
  P.loam_flat_per_sector = 40;
  P.loam_less_sharp_per_sector = 40;
  const LoamFeatures wide = run.reselect(P);
  checkSets(run.pipe, wide, P);
  checkSuppression(run, wide, 12);

  // Without suppression, adjacent picks do occur (the check above can fail).
  P.loam_suppression = 0;
  const LoamFeatures none = run.reselect(P);
  checkSets(run.pipe, none, P);
  std::set<std::uint32_t> flat(none.flat.begin(), none.flat.end());
  int adjacent = 0;
  for (const std::uint32_t p : none.flat)
  {
    const std::int64_t q = walk(run.grid(), p, 1, 1);
    adjacent += q >= 0 && flat.count(static_cast<std::uint32_t>(q));
  }
  EXPECT_GT(adjacent, 0);
}

// --- 3. occlusion and surfaces along the beam -------------------------------------------------

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

// --- 4. less flat voxel grid ------------------------------------------------------------------

TEST(LoamFeatures, LessFlatOnePointPerVoxelAndRing)
{
  Params P = baseParams();
  P.loam_less_flat_voxel = 0.0f;
  LoamRun run(boxScene(), P);
  const ScanGrid& g = run.grid();
  const std::vector<Label>& labels = run.pipe.gridLabels();
  checkSets(run.pipe, run.loam, P);

  // Voxel 0: every eligible Plane point (all but the excluded few near jumps and grazing).
  const std::vector<std::uint32_t> eligible = run.loam.less_flat;
  std::size_t planes = 0;
  for (const Label l : labels) planes += l == Label::Plane;
  std::printf("less flat, voxel 0: %zu of %zu Plane points\n", eligible.size(), planes);
  EXPECT_GT(eligible.size(), planes * 9 / 10);
  EXPECT_TRUE(std::is_sorted(eligible.begin(), eligible.end()));

  for (const float voxel : {0.2f, 0.5f, 1.0f})
  {
    P.loam_less_flat_voxel = voxel;
    const LoamFeatures L = run.reselect(P);
    checkSets(run.pipe, L, P);
    const double inv = 1.0 / static_cast<double>(voxel);
    using Key = std::tuple<int, std::int64_t, std::int64_t, std::int64_t>;  // ring, voxel
    const auto key = [&](std::uint32_t p) {
      return Key{g.ringOf(p), static_cast<std::int64_t>(std::floor(g.x[p] * inv)),
                 static_cast<std::int64_t>(std::floor(g.y[p] * inv)), static_cast<std::int64_t>(std::floor(g.z[p] * inv))};
    };
    const std::set<std::uint32_t> flat(L.flat.begin(), L.flat.end());
    std::map<Key, int> plain, flats;
    for (const std::uint32_t p : L.less_flat) (flat.count(p) ? flats : plain)[key(p)]++;
    int doubled = 0;
    for (const auto& e : plain)
      if (e.second > 1 || flats.count(e.first)) ++doubled;
    EXPECT_EQ(doubled, 0) << "voxel " << voxel << ": voxels holding a less flat point besides another";
    // Every voxel an eligible point falls in is represented.
    int missing = 0;
    for (const std::uint32_t p : eligible) missing += !plain.count(key(p)) && !flats.count(key(p));
    EXPECT_EQ(missing, 0) << "voxel " << voxel;
    // and nothing else is taken
    const std::set<std::uint32_t> el(eligible.begin(), eligible.end());
    for (const std::uint32_t p : L.less_flat) EXPECT_TRUE(el.count(p)) << "voxel " << voxel << ": " << p;
    std::printf("less flat, voxel %.1f: %zu points\n", static_cast<double>(voxel), L.less_flat.size());
    EXPECT_LT(L.less_flat.size(), eligible.size());
  }
}

// --- 5. sweep times ---------------------------------------------------------------------------

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
