// Scan grid: dual returns, as duplicates sharing their representative's label and as copies
// folded before the sort in the orders dual-return drivers emit them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <utility>
#include <vector>

#include "ring_curvature/pipeline.hpp"
#include "scan_grid_rooms.hpp"

using namespace ring_curvature;
using namespace ring_curvature::test;

namespace
{
// One point of a dual-return frame, made from a point of a single-return scan.
struct Item
{
  std::size_t from;
  int kind;  // 0: first return, 1: identical copy, 2: a second return 0.4 m further
  int rank;  // 0: first, 1: second, 2: third return of its firing
};

// A dual-return driver's order (nebula's VLP-16) over a scan of 4 rings of `per_ring` points:
// two firings' first returns, then their second returns, mostly identical copies; a few firings
// have a third return, as the second.
std::vector<Item> dualReturnOrder(std::size_t per_ring)
{
  std::vector<Item> dual_order;
  for (std::size_t ring = 0; ring < 4; ++ring)
    for (std::size_t k = 0; k + 1 < per_ring; k += 2)
    {
      const std::size_t a = ring * per_ring + k, b = a + 1;
      const int copy = k % 14 == 0 ? 2 : 1;
      dual_order.insert(dual_order.end(), {{a, 0, 0}, {b, 0, 0}, {a, copy, 1}, {b, 1, 1}});
      if (k % 22 == 0) dual_order.push_back({a, copy, 2});  // a third, as the second
    }
  return dual_order;
}

// `items` sorted stably by `key`
template <class Key>
std::vector<Item> sortedBy(const std::vector<Item>& items, Key key)
{
  std::vector<Item> sorted = items;
  std::stable_sort(sorted.begin(), sorted.end(), [&](const Item& u, const Item& v) { return key(u) < key(v); });
  return sorted;
}

// Where each of `items` sits in an order sorted stably by `key`
template <class Key>
std::vector<std::size_t> positionsBy(const std::vector<Item>& items, Key key)
{
  std::vector<std::size_t> ids(items.size()), pos(items.size());
  std::iota(ids.begin(), ids.end(), 0);
  std::stable_sort(ids.begin(), ids.end(), [&](std::size_t u, std::size_t v) { return key(items[u]) < key(items[v]); });
  for (std::size_t q = 0; q < ids.size(); ++q) pos[ids[q]] = q;
  return pos;
}

// The cloud of `items`, in their order: the points of `f` (rings of `per_ring` points), a second
// return moved 0.4 m further along its beam.
SyntheticCloud cloudOf(const ScannedFrame& f, std::size_t per_ring, const std::vector<Item>& items)
{
  const auto* src = f.cloud.bytes().data();
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
}

// The reference's verdicts: its grid and result, and where item i of the dual order sits in it.
struct Verdicts
{
  const ScanGrid& grid;
  const FrameResult& result;
  std::vector<std::size_t> at;

  // How many items of the dual order, at `pos` in a frame (g, r), have the reference's state,
  // label and primitive, and with `curvature` the same curvature bits.
  std::size_t agreeing(const ScanGrid& g, const FrameResult& r, const std::vector<std::size_t>& pos,
                       bool curvature) const
  {
    std::size_t count = 0;
    for (std::size_t i = 0; i < at.size(); ++i)
    {
      const std::size_t q = pos[i], j = at[i];
      const bool curv_same =
          !curvature || std::memcmp(&r.curvature[q], &result.curvature[j], sizeof(float)) == 0;
      const bool same = g.state[q] == grid.state[j] && r.label[q] == result.label[j] &&
                        r.primitive[q] == result.primitive[j] && curv_same;
      count += same ? 1 : 0;
    }
    return count;
  }
};
}  // namespace

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
  const std::size_t per_ring = f.cloud.size() / 4;
  const std::vector<Item> dual_order = dualReturnOrder(per_ring);
  // the reference order: by ring, then by rank, each keeping the dual order
  const auto ref_key = [per_ring](const Item& it) { return std::make_pair(it.from / per_ring, it.rank); };
  const SyntheticCloud dual = cloudOf(f, per_ring, dual_order), ref = cloudOf(f, per_ring, sortedBy(dual_order, ref_key));
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
  const Verdicts reference{gr, rr, positionsBy(dual_order, ref_key)};
  std::vector<std::size_t> as_given(dual_order.size());
  std::iota(as_given.begin(), as_given.end(), 0);
  EXPECT_EQ(reference.agreeing(gd, rd, as_given, true), dual_order.size());
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
  const std::vector<Item> late_order = sortedBy(dual_order, late_key);
  ASSERT_GT(3 * late_order.size() / 4, 4096u);  // the first three rings fill the probe
  const SyntheticCloud late = cloudOf(f, per_ring, late_order);
  Pipeline pl;
  FrameResult rl;
  ASSERT_TRUE(pl.process(late.view(), rl).ok);
  const ScanGrid& gl = pl.grid();
  EXPECT_EQ(gl.num_folded, 0u);
  EXPECT_EQ(gl.num_duplicates, gr.num_duplicates);
  EXPECT_EQ(gl.num_second_returns, gr.num_second_returns);
  // the late order and the reference both keep the dual order within each (ring, rank) group
  EXPECT_EQ(reference.agreeing(gl, rl, positionsBy(dual_order, late_key), false), dual_order.size());

  // Velodyne's firing order: the rings interleaved, a firing pair's returns of every ring in
  // turn, each ring's own sequence still the dual order. Scattered by ring, then each ring folded
  // four keys at a time against the two points before each as they came (not the last two
  // kept): a third return's twin is then the folded copy before it, whose verdict must be set
  // first (resolved in the wrong order, the third returns would take a grid position of -1).
  // The same copies are folded, with the same verdicts.
  const auto firing_key = [per_ring](const Item& it) {
    return std::make_pair((it.from % per_ring) / 2, it.from / per_ring);
  };
  const SyntheticCloud firing = cloudOf(f, per_ring, sortedBy(dual_order, firing_key));
  Pipeline pf;
  FrameResult rf;
  ASSERT_TRUE(pf.process(firing.view(), rf).ok);
  const ScanGrid& gf = pf.grid();
  EXPECT_EQ(gf.num_folded, gd.num_folded);  // the same copies, found in the same places of their ring
  EXPECT_EQ(gf.num_duplicates, gr.num_duplicates);
  EXPECT_EQ(gf.num_second_returns, gr.num_second_returns);
  EXPECT_EQ(gf.azimuth_resolution, gr.azimuth_resolution);
  EXPECT_EQ(reference.agreeing(gf, rf, positionsBy(dual_order, firing_key), true), dual_order.size());
}
