// Section 4.3: union-find over the scan grid (angular and vertical neighbours, same label, Eq
// 19-20), then box, centroid and moments per component. Linear time, no recursion.
#include "primitives/primitive_extractor.hpp"

#include "primitives/covariance_axis.hpp"
#include "primitives/primitive_sums.hpp"
#include "primitives/proximity.hpp"
#include "primitives/ring_unions.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace ring_curvature
{

namespace
{
using namespace detail;

// The duplicates' indices into their slots: `first` (at their roots) plus rank, or `total` (one
// past, dropped by the caller) where no primitive is (comp negative): one store each, no branch to
// mispredict. Duplicates get no slot_pos: the sums weight their representative instead.
void duplicateSlots(const std::uint32_t* __restrict dups, std::size_t num_dups, const std::int32_t* __restrict first,
                    const std::uint32_t* __restrict dup_root, const std::uint32_t* __restrict dup_rank,
                    std::uint32_t total, std::uint32_t* __restrict indices)
{
  for (std::size_t k = 0; k < num_dups; ++k)
  {
    // in 64 bits, f + rank is at least total exactly when f is (no wrap-around): one min
    const std::uint64_t f = static_cast<std::uint32_t>(first[dup_root[k]]);
    const auto slot = static_cast<std::uint32_t>(std::min<std::uint64_t>(f + dup_rank[k], total));
    indices[slot] = dups[k];
  }
}
}  // namespace

void PrimitiveExtractor::extract(const ScanGrid& g, const std::vector<Label>& labels, const Params& P,
                                 PrimitiveSet& out)
{
  const std::size_t m = g.size();
  out.primitives.clear();
  // indices and of_grid: every entry is written below, so a resize need not clear them
  out.of_grid.resize(m);
  // at most one run per position; num_runs counts the ones in use. Id m (none): the unwanted
  // labels' positions, one more entry in parent and comp.
  parent_.resize(m + 1);
  run_.resize(m);
  runs_.resize(m);
  comp_.resize(m + 1);
  roots_.resize(m);
  grid_size_.resize(m);
  join_.resize(m);
  const std::size_t num_runs = uniteRuns(g, labels.data(), P);
  const std::size_t num_roots = countComponents(num_runs);
  joinDuplicates(g);
  const std::uint32_t total = numberPrimitives(labels.data(), P, num_roots, out);
  fillIndices(g, num_runs, total, out);
  summarize(g, out);
}

// Most angular neighbours unite, so each ring is first cut into runs (a store per position, not two
// find() calls); only runs enter the union-find forest. Ring n is cut before the vertical unions
// of ring n-1 reach into it.
std::size_t PrimitiveExtractor::uniteRuns(const ScanGrid& g, const Label* lab, const Params& P)
{
  // a table: this is asked once or more per grid position in every loop
  const bool want[kNumLabels] = {false, true, true, true, P.rough_primitives};
  static_assert(static_cast<int>(Label::Plane) == 1 && static_cast<int>(Label::Edge) == 2 &&
                    static_cast<int>(Label::Corner) == 3 && static_cast<int>(Label::Rough) == 4,
                "want[] is indexed by Label");
  const float az_tol = P.proximity_azimuth_factor * g.azimuth_resolution;  // Eq 19
  const std::uint8_t num_wanted = P.rough_primitives ? 4 : 3;  // want[] as a range: labels 1 to num_wanted
  // Pointers and parameters in locals: through the vectors and P they would be reloaded in the loops.
  const std::uint32_t* const ring_begin = g.ring_begin.data();
  const double* const range = g.range.data();
  const float* const azimuth = g.azimuth.data();
  const std::uint8_t* const linked = g.linked.data();
  const std::int32_t* const up = g.up.empty() ? nullptr : g.up.data();
  const double range_ratio = P.proximity_range_ratio;
  const double range_min = static_cast<double>(P.proximity_range_min);
  std::uint32_t* const parent = parent_.data();
  std::uint32_t* const run = run_.data();
  std::int32_t* const comp = comp_.data();
  Run* const runs = runs_.data();
  std::uint8_t* const join = join_.data();
  const auto none = static_cast<std::uint32_t>(g.size());
  parent[none] = none;
  // A component's size counts at its root. An unwanted position's duplicate counts at `none`, which
  // starts far below zero: no test, and its component reads as rejected (negative).
  comp[none] = std::numeric_limits<std::int32_t>::min();
  std::size_t num_runs = 0, ring_runs = 0;  // ring_runs: the first run of ring n-1
  for (int n = 0; n < g.num_rings; ++n)
  {
    const std::uint32_t b = ring_begin[n], e = ring_begin[n + 1];
    const std::size_t first_run = num_runs;
    if (b < e)
    {
      angularJoins(b, e, lab, linked, range, azimuth, num_wanted, range_ratio, range_min, az_tol, join);
      num_runs = cutRing(b, e, lab, join, want, none, parent, run, comp, runs, num_runs);
    }
    // the seam: (n, K-1) and (n, 0); the ring's runs are all roots still
    if (e - b >= 2)
    {
      const Label l = lab[e - 1];
      if (want[static_cast<std::size_t>(l)] && linked[b] && lab[b] == l &&
          inRange(range[e - 1], range[b], range_ratio, range_min) && angDiff(azimuth[e - 1], azimuth[b]) <= az_tol)
        parent[run[e - 1]] = run[b];
    }
    if (n > 0 && up != nullptr)
    {
      const VerticalRing V{b,        e,         runs,          lab,       up,     range, azimuth, g.organized,
                           range_ratio * 0.5, range_min, az_tol, run, parent};
      verticalUnions(V, static_cast<std::uint32_t>(ring_runs), static_cast<std::uint32_t>(first_run), none);
    }
    ring_runs = first_run;
  }
  return num_runs;
}

// A root is its component's smallest run id (see unite), and path halving keeps parent[k] <= k, so
// in grid order parent[parent[k]] is already the root (stored back). Roots are listed in scan
// order. Each run keeps its rank among its component's points: where its indices go, no cursor.
std::size_t PrimitiveExtractor::countComponents(std::size_t num_runs)
{
  std::uint32_t* const parent = parent_.data();
  std::int32_t* const comp = comp_.data();
  Run* const runs = runs_.data();
  std::uint32_t* const roots = roots_.data();
  std::size_t num_roots = 0;
  for (std::size_t k = 0; k < num_runs; ++k)
  {
    const auto id = static_cast<std::uint32_t>(k);
    const std::uint32_t r = parent[parent[id]];
    parent[id] = r;
    roots[num_roots] = id;
    num_roots += r == id;  // without a branch: which runs start a component is data
    runs[k].rank = static_cast<std::uint32_t>(comp[r]);
    comp[r] += static_cast<std::int32_t>(runs[k].end - runs[k].begin);
  }
  // the grid points of each component, before the duplicates join (the box needs only those)
  for (std::size_t k = 0; k < num_roots; ++k) grid_size_[k] = static_cast<std::uint32_t>(comp[roots[k]]);
  return num_roots;
}

// Duplicates join their representative's primitive after its grid points and count at its grid
// position as its weight in the sums. dup_count_ is zero between frames, so a frame clears only
// its duplicates' entries (all of it if an exception left it dirty).
void PrimitiveExtractor::joinDuplicates(const ScanGrid& g)
{
  const std::uint32_t* const dups = g.duplicates.data();
  const std::size_t num_dups = g.duplicates.size();
  dup_root_.resize(num_dups);
  dup_rank_.resize(num_dups);
  dup_count_in_use_ = nullptr;
  if (num_dups == 0) return;
  const std::size_t m = g.size();
  dup_count_.resize(m);
  std::uint32_t* const dup_count = dup_count_.data();
  if (!dup_count_zero_) std::memset(dup_count, 0, m * sizeof *dup_count);
  dup_count_zero_ = false;
  dup_count_in_use_ = dup_count;
  const std::int32_t* const grid_pos = g.grid_pos.data();
  for (std::size_t k = 0; k < num_dups; ++k)
  {
    const auto pos = static_cast<std::size_t>(grid_pos[dups[k]]);
    ++dup_count[pos];
    const std::uint32_t r = parent_[run_[pos]];  // an unwanted label's position: none, comp[r] stays negative
    dup_root_[k] = r;
    dup_rank_[k] = static_cast<std::uint32_t>(comp_[r]++);
  }
}

// comp becomes the id at each root, -1 for a component too small, and grid_size is compacted to
// be indexed by id.
std::uint32_t PrimitiveExtractor::numberPrimitives(const Label* lab, const Params& P, std::size_t num_roots,
                                                   PrimitiveSet& out)
{
  std::int32_t* const comp = comp_.data();
  std::uint32_t* const roots = roots_.data();
  std::uint32_t total = 0;
  for (std::size_t k = 0; k < num_roots; ++k)
  {
    const std::uint32_t r = roots[k];
    const auto size = static_cast<std::uint32_t>(comp[r]);
    if (size < static_cast<std::uint32_t>(P.min_primitive_points))
    {
      comp[r] = -1;
      continue;
    }
    PrimitiveInfo prim;
    prim.id = static_cast<std::uint32_t>(out.primitives.size());
    prim.label = lab[runs_[r].begin];
    prim.first = total;
    prim.num_points = size;
    total += size;
    comp[r] = static_cast<std::int32_t>(prim.id);
    roots[prim.id] = r;  // the roots of the primitives, by id (prim.id <= k: read already)
    grid_size_[prim.id] = grid_size_[k];
    out.primitives.push_back(prim);
  }
  return total;
}

// Indices run by run (consecutive positions and input indices); each entry's grid position goes to
// slot_pos_, so that the sums read a primitive's grid points sequentially, in index order.
void PrimitiveExtractor::fillIndices(const ScanGrid& g, std::size_t num_runs, std::uint32_t total, PrimitiveSet& out)
{
  // not cleared: see of_grid. One more entry: the rejected duplicates' (duplicateSlots).
  out.indices.resize(std::size_t{total} + 1);
  slot_pos_.resize(std::size_t{total} + 1);
  using U4 = std::uint32_t __attribute__((vector_size(16)));
  const std::uint32_t* const ring_begin = g.ring_begin.data();
  const std::uint32_t* const parent = parent_.data();
  const std::int32_t* const comp = comp_.data();
  const Run* const runs = runs_.data();
  PrimitiveInfo* const prims = out.primitives.data();
  std::uint32_t* const indices = out.indices.data();
  std::uint32_t* const slot_pos = slot_pos_.data();
  std::int32_t* const of_grid = out.of_grid.data();
  const std::uint32_t* const index = g.index.data();
  const auto m = static_cast<std::uint32_t>(g.size());
  int n = 0;
  // of_grid is written once, the gaps before each reported run with -1 (not all of it first)
  std::uint32_t written = 0;
  for (std::size_t k = 0; k < num_runs; ++k)
  {
    const std::uint32_t s = runs[k].begin, t = runs[k].end;
    const std::int32_t id = comp[parent[k]];
    if (id < 0) continue;
    for (std::uint32_t p = written; p < s; ++p) of_grid[p] = -1;
    written = t;
    while (s >= ring_begin[n + 1]) ++n;
    PrimitiveInfo& pr = prims[id];
    // runs come in grid order, so in ring order: the first one has the lowest ring
    if (runs[k].rank == 0) pr.ring_min = static_cast<std::uint16_t>(n);
    pr.ring_max = static_cast<std::uint16_t>(n);
    const std::uint32_t slot = pr.first + runs[k].rank;
    if (t - s < 4)
    {
      for (std::uint32_t p = s, q = slot; p < t; ++p, ++q)
      {
        of_grid[p] = id;
        indices[q] = index[p];
        slot_pos[q] = p;
      }
      continue;
    }
    // Four positions a step (three scalar stores a position would bound the loop), the last step
    // ending at the run's end, overlapping the one before with the same values.
    const U4 ids = U4{0, 0, 0, 0} + static_cast<std::uint32_t>(id);
    const auto step = [index, indices, slot_pos, of_grid, s, slot, ids](std::uint32_t o) {
      U4 v;
      std::memcpy(&v, index + s + o, sizeof v);
      std::memcpy(indices + slot + o, &v, sizeof v);
      const U4 pos = U4{0, 1, 2, 3} + (s + o);
      std::memcpy(slot_pos + slot + o, &pos, sizeof pos);
      std::memcpy(of_grid + s + o, &ids, sizeof ids);
    };
    const std::uint32_t len = t - s;
    for (std::uint32_t o = 0; o + 4 < len; o += 4) step(o);
    step(len - 4);
  }
  for (std::uint32_t p = written; p < m; ++p) of_grid[p] = -1;
  // Duplicates into their slots: comp becomes the first slot at each primitive's root
  for (std::size_t id = 0; id < out.primitives.size(); ++id)
    comp_[roots_[id]] = static_cast<std::int32_t>(prims[id].first);
  duplicateSlots(g.duplicates.data(), g.duplicates.size(), comp_.data(), dup_root_.data(), dup_rank_.data(), total,
                 indices);
  out.indices.resize(total);
}

// Box, centroid, moments and axes, primitive by primitive (primitive_sums.cpp: one pass in double,
// each grid point weighted by its duplicates; the centroid is the mean rounded to float).
void PrimitiveExtractor::summarize(const ScanGrid& g, PrimitiveSet& out)
{
  std::uint32_t* const dup_count = dup_count_in_use_;
  for (auto& pr : out.primitives)
  {
    PrimitiveSums S;
    primitiveSums(slot_pos_.data() + pr.first, grid_size_[pr.id], pr.num_points, dup_count, g.x.data(), g.y.data(),
                  g.z.data(), S);
    pr.bbox_min = Eigen::Vector3f(S.lo[0], S.lo[1], S.lo[2]);
    pr.bbox_max = Eigen::Vector3f(S.hi[0], S.hi[1], S.hi[2]);
    pr.centroid = Eigen::Vector3f(S.centroid[0], S.centroid[1], S.centroid[2]);
    const Eigen::Vector3d c = pr.centroid.cast<double>();
    Eigen::Matrix3d cov;
    cov << S.m[0], S.mxy[0], S.m[2], S.mxy[0], S.m[1], S.mxy[1], S.m[2], S.mxy[1], S.m[3];
    cov /= static_cast<double>(pr.num_points);
    pr.covariance = cov.cast<float>();
    Eigen::Vector3d eigenvalues, axis;  // (covariance_axis.hpp: computeDirect's steps, one column)
    covarianceAxis(cov, pr.label == Label::Plane ? 0 : 2, eigenvalues, axis);
    const Eigen::Vector3d ev = eigenvalues.cwiseMax(0.0);  // ascending
    pr.eigenvalues = ev.cast<float>();
    if (pr.label == Label::Plane && axis.dot(c) > 0) axis = -axis;  // a plane's normal faces the sensor
    pr.axis = axis.cast<float>();
    pr.rms_error = static_cast<float>(std::sqrt(pr.label == Label::Plane ? ev(0) : ev(0) + ev(1)));
  }
  // the counts back to zero: the duplicates' entries one by one where they are few, else the
  // whole array (a duplicate for nearly every position on dual-return frames)
  const std::size_t num_dups = g.duplicates.size(), m = g.size();
  if (dup_count == nullptr) return;
  if (num_dups * 16 < m)
    for (std::size_t k = 0; k < num_dups; ++k) dup_count[g.grid_pos[g.duplicates[k]]] = 0;
  else
    std::memset(dup_count, 0, m * sizeof *dup_count);
  dup_count_zero_ = true;
}

}  // namespace ring_curvature
