// Issue 30 (item 1): LOAM's feature sets (loam/loam_selector.cpp) on ray-cast scenes whose answer
// is known: quotas per ring and sector, neighbour suppression and the less flat voxel grid (LOAM's
// other rules, the occluded side of depth jumps and surfaces along the beam, are in
// test_loam_selector_exclusions.cpp; the sweep times in test_loam_selector_sweep_time.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <random>
#include <set>
#include <tuple>
#include <vector>
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

TEST(LoamFeatures, RoughPointsOnlyAtJumpsAndOnlyLessSharp)
{
  // A hedge of random depth in front of a wall: Rough points, which must not become features but
  // for their depth jumps, which are less sharp.
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
  const auto roughIn = [&](const std::vector<std::uint32_t>& v) {
    std::size_t n = 0;
    for (const std::uint32_t p : v) n += pipe.gridLabels()[p] == Label::Rough;
    return n;
  };
  const std::size_t outlines = roughIn(L.less_sharp);
  std::printf("hedge: %zu Rough points at jumps in less sharp of %zu\n", outlines, L.less_sharp.size());
  EXPECT_GT(outlines, 10u);
  EXPECT_LT(outlines, rough / 2);  // the jumps, not the whole hedge
  EXPECT_EQ(roughIn(L.sharp) + roughIn(L.flat) + roughIn(L.less_flat), 0u);

  // Off: no Rough point in any set, and the Edge/Corner picks are unchanged.
  Params off = P;
  off.loam_rough_jump = 0.0f;
  Pipeline pipe_off(off);
  ASSERT_TRUE(pipe_off.process(c.view(), r).ok);
  LoamFeatures L0;
  pipe_off.selectLoamFeatures(c.view(), L0);
  checkSets(pipe_off, L0, off);
  EXPECT_EQ(roughIn(L0.less_sharp), 0u);
  EXPECT_EQ(L0.less_sharp.size() + outlines, L.less_sharp.size());
  EXPECT_EQ(L0.sharp, L.sharp);
  EXPECT_EQ(L0.flat, L.flat);
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

// --- 3. less flat voxel grid ------------------------------------------------------------------

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

}  // namespace
