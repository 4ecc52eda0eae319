// Scan grid: seam, gaps, ring counts, empty frames, duplicates, shuffled and organized input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <random>
#include <utility>

#include "../support/ray_scene.hpp"
#include "common/float_bits.hpp"
#include "ring_curvature/pipeline.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
constexpr double kDeg = 3.14159265358979323846 / 180;

// The square room (ray_scene.hpp) without ground: the ground at -100 m is out of range, so the
// rings stay on the walls.
RayScene room() { return squareRoom(-100); }

// The room standing on level ground, 16 beams, 5 mm noise: walls, creases, ground, jumps.
ScannedFrame roomOnGround()
{
  RayScene s = room();
  s.ground_z = -1.8;
  return scan(s, SensorModel::uniform(16, -15, 15, 0.2), 0.005, 3);
}

std::size_t count(const FrameResult& r, Label l)
{
  return static_cast<std::size_t>(std::count(r.label.begin(), r.label.end(), static_cast<std::uint8_t>(l)));
}
}  // namespace

TEST(ScanGrid, EmptyFrameIsFine)
{
  SyntheticCloud c;
  Pipeline p;
  FrameResult r;
  const Status st = p.process(c.view(), r);
  EXPECT_TRUE(st.ok) << st.message;
  EXPECT_TRUE(r.label.empty());
  EXPECT_TRUE(r.primitives.primitives.empty());
}

TEST(ScanGrid, RingCounts16To128)
{
  for (int beams : {1, 16, 32, 64, 128})
  {
    const SensorModel s = SensorModel::uniform(beams, -10, 10, 0.4);
    const ScannedFrame f = scan(room(), s);
    Pipeline p;
    FrameResult r;
    ASSERT_TRUE(p.process(f.cloud.view(), r).ok) << beams;
    EXPECT_EQ(p.grid().num_rings, beams);
    EXPECT_EQ(p.grid().size(), f.cloud.size());  // every return on the grid
    for (int n = 0; n < beams; ++n) EXPECT_TRUE(p.grid().ring_closed[static_cast<std::size_t>(n)]) << beams << " ring " << n;
    // 4 corners per ring, each an Edge (peak only), all else Plane
    EXPECT_EQ(count(r, Label::Edge), static_cast<std::size_t>(4 * beams)) << beams << " beams";
    EXPECT_EQ(count(r, Label::Plane), f.cloud.size() - 4 * static_cast<std::size_t>(beams)) << beams;
    EXPECT_NEAR(p.grid().azimuth_resolution, 0.4 * kDeg, 1e-5);
    if (beams > 1)
    {
      // walls join across rings into 4 planar patches (a patch may not cross a corner)
      std::size_t planes = 0;
      for (const auto& pr : r.primitives.primitives) planes += pr.label == Label::Plane ? 1 : 0;
      EXPECT_EQ(planes, 4u) << beams;
    }
  }
}

TEST(ScanGrid, FeatureAcrossTheSeamIsFoundOnce)
{
  // Rotate the room so that one corner sits exactly on the 0/360 deg seam (azimuth 180 deg),
  // and start the sweep there: the corner's samples are split between the two ends of the ring.
  RayScene s = room();
  for (auto& b : s.boxes)
  {
    const double c = std::cos(-45 * kDeg), sn = std::sin(-45 * kDeg);
    const double x = b.cx, y = b.cy;
    b.cx = c * x - sn * y;
    b.cy = sn * x + c * y;
    b.yaw = -45 * kDeg;
  }
  const SensorModel m = SensorModel::uniform(4, -5, 5, 0.25);
  const ScannedFrame f = scan(s, m, 0.0, 1, 3.14159265358979323846);  // sweep starts at the seam
  Pipeline p;
  FrameResult r;
  ASSERT_TRUE(p.process(f.cloud.view(), r).ok);
  EXPECT_EQ(count(r, Label::Edge), 16u);  // 4 corners x 4 rings, the seam corner not doubled nor lost
  std::size_t planes = 0;
  for (const auto& pr : r.primitives.primitives) planes += pr.label == Label::Plane ? 1 : 0;
  EXPECT_EQ(planes, 4u);  // the wall split by the seam is one patch
}

TEST(ScanGrid, NaNGapsBreakTheCurve)
{
  const SensorModel m = SensorModel::uniform(1, 0, 0, 0.4);
  ScannedFrame f = scan(room(), m);
  // punch a 10-sample hole in the middle of a wall (azimuth 0 is the middle of the +x wall)
  SyntheticCloud holed;
  const std::size_t n = f.cloud.size();
  std::vector<std::size_t> gone;
  for (std::size_t i = 0; i < n; ++i)
  {
    const auto* rec = f.cloud.bytes().data() + i * f.cloud.pointStep();
    float x, y, z;
    std::memcpy(&x, rec, 4);
    std::memcpy(&y, rec + 4, 4);
    std::memcpy(&z, rec + 8, 4);
    if (i >= 100 && i < 110)
    {
      holed.addNaN(0);
      gone.push_back(i);
    }
    else
      holed.add(x, y, z, 0);
  }
  Pipeline p;
  FrameResult r;
  ASSERT_TRUE(p.process(holed.view(), r).ok);
  for (std::size_t i : gone)
  {
    EXPECT_EQ(r.label[i], 0) << i;
    EXPECT_TRUE(std::isnan(r.curvature[i]));
  }
  // no curvature invented across the hole: the samples beside it have a one-sided neighbourhood
  EXPECT_TRUE(std::isnan(r.curvature[99]));
  EXPECT_TRUE(std::isnan(r.curvature[110]));
  EXPECT_EQ(r.label[99], static_cast<std::uint8_t>(Label::Plane));
  EXPECT_EQ(count(r, Label::Edge), 4u);
  EXPECT_EQ(p.grid().num_valid + 10, n);
}

TEST(ScanGrid, AnyInputOrderGivesTheSameLabels)
{
  // Drivers emit rings in firing order: counter-clockwise or clockwise, starting anywhere. The
  // grid takes a presorted ring as it is (reversed or rotated to the seam when needed) and sorts
  // the others; every ordering, down to a full shuffle, must give the same labels per point.
  const ScannedFrame f = roomOnGround();
  Pipeline p;
  FrameResult ref;
  ASSERT_TRUE(p.process(f.cloud.view(), ref).ok);
  const std::size_t n = f.cloud.size(), per_ring = n / 16;
  auto reorder = [&](auto index_of) {  // point i of the new cloud is point index_of(i) of f
    SyntheticCloud c;
    c.bytes().resize(f.cloud.bytes().size());
    std::vector<std::size_t> from(n);
    for (std::size_t i = 0; i < n; ++i)
    {
      from[i] = index_of(i);
      std::memcpy(c.bytes().data() + i * 22, f.cloud.bytes().data() + from[i] * 22, 22);
    }
    FrameResult r;
    EXPECT_TRUE(p.process(c.view(), r).ok);
    std::size_t same = 0;
    for (std::size_t i = 0; i < n; ++i) same += r.label[i] == ref.label[from[i]] ? 1 : 0;
    return same;
  };
  // every ring reversed (a clockwise sensor)
  EXPECT_EQ(reorder([&](std::size_t i) { return n - 1 - i; }), n);
  // every ring starting a third of the way round (not at the seam)
  EXPECT_EQ(reorder([&](std::size_t i) {
              const std::size_t ring = i / per_ring, k = i % per_ring;
              return ring * per_ring + (k + per_ring / 3) % per_ring;
            }),
            n);
  // reversed and rotated
  EXPECT_EQ(reorder([&](std::size_t i) {
              const std::size_t ring = i / per_ring, k = per_ring - 1 - i % per_ring;
              return ring * per_ring + (k + 2 * per_ring / 5) % per_ring;
            }),
            n);
  // a few neighbours swapped (not monotonic: the sort's fallback)
  EXPECT_EQ(reorder([&](std::size_t i) { return i % 97 == 5 ? i + 1 : (i % 97 == 6 ? i - 1 : i); }), n);
  // every point anywhere (rings interleaved, no order at all)
  std::vector<std::size_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(5));
  EXPECT_EQ(reorder([&](std::size_t i) { return perm[i]; }), n);
}

TEST(ScanGrid, RingsFromElevationMatchTheRingField)
{
  // A cloud without `ring` (opt-in ring_from_elevation): beams are found by clustering elevation
  // angles, numbered from the lowest up like velodyne_pointcloud, so the result must equal the
  // one computed with the driver's ring field.
  const ScannedFrame f = roomOnGround();
  Pipeline with_field;
  FrameResult ref;
  ASSERT_TRUE(with_field.process(f.cloud.view(), ref).ok);

  PointCloudView v = f.cloud.view();
  v.ring = {};
  Pipeline refuses;
  FrameResult r;
  EXPECT_FALSE(refuses.process(v, r).ok);  // not without opting in
  Params opt_in;
  opt_in.ring_from_elevation = true;
  Pipeline derived(opt_in);
  ASSERT_TRUE(derived.process(v, r).ok);
  EXPECT_EQ(derived.grid().num_rings, 16);
  EXPECT_EQ(r.label, ref.label);
  EXPECT_EQ(r.primitive, ref.primitive);
}

TEST(ScanGrid, DualReturnDuplicatesShareTheirRepresentativeLabel)
{
  const SensorModel m = SensorModel::uniform(4, -5, 5, 0.4);
  const ScannedFrame f = scan(room(), m);
  SyntheticCloud dual;
  const std::size_t n = f.cloud.size();
  for (std::size_t i = 0; i < n; ++i)  // every firing twice, as a dual-return driver emits them
    for (int t = 0; t < 2; ++t)
      dual.bytes().insert(dual.bytes().end(), f.cloud.bytes().begin() + static_cast<std::ptrdiff_t>(i * 22),
                          f.cloud.bytes().begin() + static_cast<std::ptrdiff_t>(i * 22 + 22));
  Pipeline p;
  FrameResult single, r;
  ASSERT_TRUE(p.process(f.cloud.view(), single).ok);
  ASSERT_TRUE(p.process(dual.view(), r).ok);
  EXPECT_EQ(p.grid().num_duplicates, n);
  for (std::size_t i = 0; i < n; ++i)
  {
    EXPECT_EQ(r.label[2 * i], single.label[i]);
    EXPECT_EQ(r.label[2 * i + 1], single.label[i]);
    EXPECT_EQ(r.primitive[2 * i], r.primitive[2 * i + 1]);
  }
  // primitives list both copies
  for (const auto& pr : r.primitives.primitives)
    for (std::uint32_t j = 0; j < pr.num_points; ++j)
      EXPECT_EQ(r.primitive[r.primitives.indices[pr.first + j]], static_cast<std::int32_t>(pr.id));
}

TEST(ScanGrid, FoldedDualReturnsGetTheVerdictOfTheSort)
{
  // A dual-return driver's order (nebula's VLP-16): two firings' first returns, then their second
  // returns, which are mostly identical copies. The grid folds a copy found among the last two
  // points of its ring before sorting; the verdict must be the one the sort and removeDuplicates
  // reach without folding. The reference holds the same points with every ring's first returns,
  // then its second returns, then its third ones (same order within each firing), where no
  // point is next to its twin and nothing is folded.
  const ScannedFrame f = scan(room(), SensorModel::uniform(4, -5, 5, 0.4));
  const std::size_t n = f.cloud.size(), per_ring = n / 4;
  const auto* src = f.cloud.bytes().data();
  struct Item
  {
    std::size_t from;
    int kind;  // 0: first return, 1: identical copy, 2: a second return 0.4 m further
    int rank;  // 0: first, 1: second, 2: third return of its firing
  };
  std::vector<Item> dual_order;
  for (std::size_t ring = 0; ring < 4; ++ring)
    for (std::size_t k = 0; k + 1 < per_ring; k += 2)
    {
      const std::size_t a = ring * per_ring + k, b = a + 1;
      const int copy = k % 14 == 0 ? 2 : 1;
      dual_order.insert(dual_order.end(), {{a, 0, 0}, {b, 0, 0}, {a, copy, 1}, {b, 1, 1}});
      if (k % 22 == 0) dual_order.push_back({a, copy, 2});  // a third, as the second
    }
  // the reference order: by ring, then by rank, each keeping the dual order
  const auto ref_key = [per_ring](const Item& it) { return std::make_pair(it.from / per_ring, it.rank); };
  std::vector<Item> ref_order = dual_order;
  std::stable_sort(ref_order.begin(), ref_order.end(),
                   [&](const Item& u, const Item& v) { return ref_key(u) < ref_key(v); });
  auto build = [&](const std::vector<Item>& items) {
    SyntheticCloud c;
    for (const Item& it : items)
    {
      float xyz[3];
      std::memcpy(xyz, src + it.from * 22, sizeof xyz);
      const double r = std::sqrt(double(xyz[0]) * xyz[0] + double(xyz[1]) * xyz[1] + double(xyz[2]) * xyz[2]);
      const double s = it.kind == 2 ? (r + 0.4) / r : 1.0;
      c.add(xyz[0] * s, xyz[1] * s, xyz[2] * s, static_cast<int>(it.from / per_ring));
    }
    return c;
  };
  const SyntheticCloud dual = build(dual_order), ref = build(ref_order);
  Pipeline pd, pr;
  FrameResult rd, rr;
  ASSERT_TRUE(pd.process(dual.view(), rd).ok);
  ASSERT_TRUE(pr.process(ref.view(), rr).ok);
  const ScanGrid &gd = pd.grid(), &gr = pr.grid();
  EXPECT_GT(gd.num_folded, dual_order.size() / 3);  // most copies were folded
  EXPECT_EQ(gr.num_folded, 0u);
  EXPECT_GT(gd.num_second_returns, 0u);
  EXPECT_EQ(gd.num_valid, gr.num_valid);
  EXPECT_EQ(gd.num_duplicates, gr.num_duplicates);
  EXPECT_EQ(gd.num_second_returns, gr.num_second_returns);
  EXPECT_EQ(gd.azimuth_resolution, gr.azimuth_resolution);
  // where each item of the dual order sits in an order sorted stably by `key`
  const auto positions_by = [&](auto key) {
    std::vector<std::size_t> ids(dual_order.size()), pos(dual_order.size());
    std::iota(ids.begin(), ids.end(), 0);
    std::stable_sort(ids.begin(), ids.end(),
                     [&](std::size_t u, std::size_t v) { return key(dual_order[u]) < key(dual_order[v]); });
    for (std::size_t q = 0; q < ids.size(); ++q) pos[ids[q]] = q;
    return pos;
  };
  const std::vector<std::size_t> at = positions_by(ref_key);  // in the reference
  // How many items of the dual order, at `pos` in a frame (g, r), have the reference's state,
  // label and primitive, and with `curvature` the same curvature bits.
  const auto agreeing = [&](const ScanGrid& g, const FrameResult& r, const std::vector<std::size_t>& pos,
                            bool curvature) {
    std::size_t count = 0;
    for (std::size_t i = 0; i < dual_order.size(); ++i)
    {
      const std::size_t q = pos[i], j = at[i];
      const bool curv_same = !curvature || std::memcmp(&r.curvature[q], &rr.curvature[j], sizeof(float)) == 0;
      count += g.state[q] == gr.state[j] && r.label[q] == rr.label[j] && r.primitive[q] == rr.primitive[j] && curv_same
                   ? 1
                   : 0;
    }
    return count;
  };
  std::vector<std::size_t> as_given(dual_order.size());
  std::iota(as_given.begin(), as_given.end(), 0);
  EXPECT_EQ(agreeing(gd, rd, as_given, true), dual_order.size());
  ASSERT_EQ(rd.primitives.primitives.size(), rr.primitives.primitives.size());
  for (std::size_t k = 0; k < rd.primitives.primitives.size(); ++k)
    EXPECT_EQ(rd.primitives.primitives[k].num_points, rr.primitives.primitives[k].num_points);

  // Folding stops when the frame's first 4096 points fold nothing (a single-return frame): here
  // the first three rings come in the reference order (no twin next to its copy) and only the
  // last in dual order. Nothing is folded, and every verdict is still the reference's.
  const auto late_key = [per_ring](const Item& it) {
    const std::size_t ring = it.from / per_ring;
    return std::make_pair(ring, ring < 3 ? it.rank : 0);
  };
  std::vector<Item> late_order = dual_order;
  std::stable_sort(late_order.begin(), late_order.end(),
                   [&](const Item& u, const Item& v) { return late_key(u) < late_key(v); });
  ASSERT_GT(3 * late_order.size() / 4, 4096u);  // the first three rings fill the probe
  const SyntheticCloud late = build(late_order);
  Pipeline pl;
  FrameResult rl;
  ASSERT_TRUE(pl.process(late.view(), rl).ok);
  const ScanGrid& gl = pl.grid();
  EXPECT_EQ(gl.num_folded, 0u);
  EXPECT_EQ(gl.num_duplicates, gr.num_duplicates);
  EXPECT_EQ(gl.num_second_returns, gr.num_second_returns);
  // the late order and the reference both keep the dual order within each (ring, rank) group
  EXPECT_EQ(agreeing(gl, rl, positions_by(late_key), false), dual_order.size());

  // Velodyne's firing order: the rings interleaved, a firing pair's returns of every ring in
  // turn, each ring's own sequence still the dual order. Scattered by ring, then each ring folded
  // four keys at a time against the two points before each as they came (not the last two
  // kept): a third return's twin is then the folded copy before it, whose verdict must be set
  // first (resolved in the wrong order, the third returns would take a grid position of -1).
  // The same copies are folded, with the same verdicts.
  const auto firing_key = [per_ring](const Item& it) {
    return std::make_pair((it.from % per_ring) / 2, it.from / per_ring);
  };
  std::vector<Item> firing_order = dual_order;
  std::stable_sort(firing_order.begin(), firing_order.end(),
                   [&](const Item& u, const Item& v) { return firing_key(u) < firing_key(v); });
  const SyntheticCloud firing = build(firing_order);
  Pipeline pf;
  FrameResult rf;
  ASSERT_TRUE(pf.process(firing.view(), rf).ok);
  const ScanGrid& gf = pf.grid();
  EXPECT_EQ(gf.num_folded, gd.num_folded);  // the same copies, found in the same places of their ring
  EXPECT_EQ(gf.num_duplicates, gr.num_duplicates);
  EXPECT_EQ(gf.num_second_returns, gr.num_second_returns);
  EXPECT_EQ(gf.azimuth_resolution, gr.azimuth_resolution);
  EXPECT_EQ(agreeing(gf, rf, positions_by(firing_key), true), dual_order.size());
}

TEST(ScanGrid, OrganizedCloudUsesRowsAndColumns)
{
  // Ouster-like: rows are beams, ring 0 at the top, NaN where there is no return.
  const SensorModel m = SensorModel::uniform(8, -10, 10, 360.0 / 512);
  RayScene s = room();
  const ScannedFrame f = scan(s, m);
  // reverse row order (ring 0 = highest) and drop a few returns (at other columns on each row)
  SyntheticCloud org;
  const std::size_t cols = f.cloud.size() / 8;
  for (int row = 7; row >= 0; --row)
    for (std::size_t c = 0; c < cols; ++c)
    {
      const std::size_t i = static_cast<std::size_t>(row) * cols + c;
      if (c % 50 == static_cast<std::size_t>(7 + 3 * row))
      {
        org.addNaN(7 - row);
        continue;
      }
      float x, y, z;
      std::memcpy(&x, f.cloud.bytes().data() + i * 22, 4);
      std::memcpy(&y, f.cloud.bytes().data() + i * 22 + 4, 4);
      std::memcpy(&z, f.cloud.bytes().data() + i * 22 + 8, 4);
      org.add(x, y, z, 7 - row);
    }
  Pipeline p;
  FrameResult r;
  ASSERT_TRUE(p.process(org.view(8), r).ok);
  EXPECT_TRUE(p.grid().organized);
  EXPECT_EQ(p.grid().num_rings, 8);
  EXPECT_EQ(count(r, Label::Edge), 32u);
  // the vertical neighbour is the same column one row up, none where that return is missing
  const ScanGrid& g = p.grid();
  std::size_t missing_above = 0;
  for (std::size_t pos = 0; pos < g.size(); ++pos)
  {
    const std::size_t i = g.index[pos], above = i + cols;
    const bool on_grid = above < g.num_input && g.state[above] == PointState::OnGrid;
    missing_above += above < g.num_input && !on_grid ? 1 : 0;
    EXPECT_EQ(g.up[pos], on_grid ? g.grid_pos[above] : -1) << pos;
  }
  EXPECT_GT(missing_above, 20u);
  std::size_t planes = 0;
  for (const auto& pr : r.primitives.primitives) planes += pr.label == Label::Plane ? 1 : 0;
  EXPECT_EQ(planes, 4u);
}

TEST(ScanGrid, RejectsBadViewsWithAClearMessage)
{
  SyntheticCloud c;
  c.add(1, 2, 3, 0);
  c.add(1, 2, 3.1, 0);
  Pipeline p;
  FrameResult r;
  PointCloudView v = c.view();
  v.ring = {};
  Status st = p.process(v, r);
  EXPECT_FALSE(st.ok);
  EXPECT_NE(st.message.find("ring"), std::string::npos) << st.message;
  v = c.view();
  v.ring.type = ScalarType::Float32;
  st = p.process(v, r);
  EXPECT_NE(st.message.find("integer"), std::string::npos) << st.message;
  v = c.view();
  v.data_size -= 1;
  st = p.process(v, r);
  EXPECT_NE(st.message.find("truncated"), std::string::npos) << st.message;
  v = c.view();
  v.x.offset = 20;
  st = p.process(v, r);
  EXPECT_NE(st.message.find("outside the point record"), std::string::npos) << st.message;
  v = c.view();
  v.y.offset = 2;
  st = p.process(v, r);
  EXPECT_NE(st.message.find("overlap"), std::string::npos) << st.message;
  Params small;
  small.max_rings = 1;
  Pipeline q(small);
  c.add(1, 2, 3.2, 5);
  st = q.process(c.view(), r);
  EXPECT_NE(st.message.find("max_rings"), std::string::npos) << st.message;
  // and the next good frame is processed normally
  SyntheticCloud good;
  good.add(1, 2, 3, 0);
  good.add(1, 2.1, 3, 0);
  good.add(1, 2.2, 3, 0);
  EXPECT_TRUE(q.process(good.view(), r).ok);
  EXPECT_EQ(r.label.size(), 3u);
}

// The input pass's vectorized loops (their clones included): every point on the grid must carry
// exactly fastAtan2(y, x) of its float coordinates and the double range sqrt((x x + y y) + z z), special
// values included (signed zeros, subnormals, |x| = |y|, the axes), and points out of range or NaN
// must stay off the grid.
TEST(ScanGrid, InputPassGivesExactAzimuthsAndRanges)
{
  const float specials[] = {0.0f, -0.0f, 1e-40f, -1e-40f, 1.0f, -1.0f, 2.5f, -2.5f, 1e3f, -1e3f, 7.0e-3f, -3.0f};
  SyntheticCloud c;
  std::vector<float> xs, ys, zs;
  int ring = 0;
  const auto add = [&](float x, float y, float z) {
    c.add(x, y, z, ring);
    xs.push_back(x);
    ys.push_back(y);
    zs.push_back(z);
    ring = (ring + 1) % 16;
  };
  for (float x : specials)
    for (float y : specials) add(x, y, 4.0f);
  add(std::numeric_limits<float>::quiet_NaN(), 1.0f, 1.0f);
  add(0.01f, 0.0f, 0.0f);  // below min_range
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-50.0f, 50.0f);
  for (int k = 0; k < 20003; ++k) add(u(rng), u(rng), u(rng) * 0.1f);  // not a multiple of 8
  Pipeline p;
  FrameResult r;
  ASSERT_TRUE(p.process(c.view(), r).ok);
  const ScanGrid& g = p.grid();
  std::size_t on_grid = 0;
  for (std::size_t i = 0; i < xs.size(); ++i)
  {
    const double x = xs[i], y = ys[i], z = zs[i];
    const double range = std::sqrt(x * x + y * y + z * z);
    if (!(range >= p.params().min_range && range <= p.params().max_range))
    {
      EXPECT_EQ(g.state[i], PointState::Invalid) << i;
      continue;
    }
    if (g.state[i] != PointState::OnGrid) continue;  // a duplicate of the same azimuth and range
    ++on_grid;
    const auto pos = static_cast<std::size_t>(g.grid_pos[i]);
    ASSERT_EQ(g.index[pos], i);
    const float az = fastAtan2(ys[i], xs[i]);
    EXPECT_EQ(std::memcmp(&g.azimuth[pos], &az, sizeof az), 0) << i << ": " << g.azimuth[pos] << " vs " << az;
    EXPECT_EQ(std::memcmp(&g.range[pos], &range, sizeof range), 0) << i;
    EXPECT_EQ(g.x[pos], x);
    EXPECT_EQ(g.z[pos], z);
  }
  // (random azimuths: some points fall within one firing of another and leave the grid as
  // second returns; most stay)
  EXPECT_GT(on_grid, xs.size() / 2);
}
