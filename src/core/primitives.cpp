// Section 4.3: union-find over the scan grid (angular and vertical neighbours, same label,
// proximity by Eq 19-20), then box, centroid and moments per component. Linear time, no
// recursion.
#include "ring_curvature/primitives.hpp"

#include "angles.hpp"
#include "covariance_axis.hpp"
#include "cpu_tuning.hpp"
#include "primitive_runs.hpp"
#include "primitive_sums.hpp"
#include "proximity.hpp"
#include "simd_clones.hpp"
#include "vertical_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>
#endif
#include <limits>

namespace ring_curvature
{

namespace
{
// Which positions (b, e) of a ring join their predecessor's run: same wanted label (labels 1 to
// num_wanted), linked, and close by Eq 19-20, in the operand order of the pair (p-1, p). Each
// position on its own, without branches: the compiler vectorizes the loop (16 positions an
// iteration; 4 doubles a vector with AVX2), where the run loop took one position at a time
// with a branch per test.
RC_SIMD_CLONES void angularJoins(std::size_t b, std::size_t e, const Label* __restrict lab,
                                 const std::uint8_t* __restrict linked, const double* __restrict range,
                                 const float* __restrict azimuth, std::uint8_t num_wanted, double range_ratio,
                                 double range_min, float az_tol, std::uint8_t* __restrict join)
{
  for (std::size_t p = b + 1; p < e; ++p)  // size_t: a uint32 index that may wrap does not vectorize
  {
    const auto l = static_cast<std::uint8_t>(lab[p]), l_prev = static_cast<std::uint8_t>(lab[p - 1]);
    const double ra = range[p - 1], rb = range[p];
    const bool in_range = inRange(ra, rb, range_ratio, range_min);
    join[p] = (static_cast<std::uint8_t>(l - 1) < num_wanted) & (linked[p] != 0) & (l_prev == l) & in_range &
              (angDiff(azimuth[p - 1], azimuth[p]) <= az_tol);  // Eq 19
  }
}

// GCC vector types for the range tests of the vertical unions
using D4 = double __attribute__((vector_size(32)));
using I4 = long long __attribute__((vector_size(32)));

inline std::uint32_t find(std::uint32_t* parent, std::uint32_t a)
{
  while (parent[a] != a)
  {
    parent[a] = parent[parent[a]];  // path halving
    a = parent[a];
  }
  return a;
}

inline void unite(std::uint32_t* parent, std::uint32_t a, std::uint32_t b)
{
  a = find(parent, a);
  b = find(parent, b);
  if (a == b) return;
  if (a < b) std::swap(a, b);
  parent[a] = b;  // the smaller run id is the root: components are numbered in scan order
}

// The loops over a ring below are functions of their own (not inlined): inside extract, with
// its two dozen pointers and parameters live, the compiler kept the loops' pointers on the
// stack and reloaded them in the loops.

// Cuts ring [b, e) into runs from join[] (see Run). The runs of wanted labels are listed and
// numbered in grid order (run ids: the union-find forest and the component counts are per run,
// dense arrays of a few thousand entries, where per position they spread over the grid's
// size); each run is a root of its own. Every position of an unwanted label gets the id
// `none`. Returns the new number of listed runs.
__attribute__((noinline)) std::size_t cutRing(std::uint32_t b, std::uint32_t e, const Label* __restrict lab,
                                              const std::uint8_t* __restrict join, const bool* __restrict want,
                                              std::uint32_t none, std::uint32_t* __restrict parent,
                                              std::uint32_t* __restrict run, std::int32_t* __restrict comp,
                                              PrimitiveExtractor::Run* __restrict runs, std::size_t num_runs)
{
  // A run's entries are written when it opens, at the next free id, whether wanted or not; an
  // unwanted run does not take the id (the next run writes it again): no branch on the label.
  const auto open = [lab, want, none, parent, comp, runs](std::uint32_t p, std::size_t k) {
    const bool wanted = want[static_cast<std::size_t>(lab[p])];
    const auto id = static_cast<std::uint32_t>(k);
    runs[k].begin = p;
    parent[k] = id;
    comp[k] = 0;
    return wanted ? id : none;
  };
  // (a loop per run: with one loop over positions the compiler prepared the next run's
  // entries at every position)
  std::uint32_t p = b;
  do
  {
    const std::uint32_t id = open(p, num_runs);
    run[p] = id;
    for (++p; p < e && join[p]; ++p) run[p] = id;
    runs[num_runs].end = p;
    num_runs += id != none;
  } while (p < e);
  return num_runs;
}

// Position p of run rp (label l, end pe) with the nearest sample above, uu, and the ones beside
// it, c1 and c2, where in0, in1, in2 say which of the three are within Eq 20 of p: see
// verticalUnions. Returns the last position it covers: p, or beyond it where the positions after
// it can only unite what is united now.
__attribute__((always_inline)) inline std::uint32_t joinAbove(const VerticalRing& V, std::uint32_t rp, Label l,
                                                              std::uint32_t p, std::uint32_t pe, std::uint32_t uu,
                                                              std::uint32_t c1, std::uint32_t c2, bool in0, bool in1,
                                                              bool in2, std::uint32_t& last_rp, std::uint32_t& last_rq)
{
  const Label* const lab = V.lab;
  const float* const azimuth = V.azimuth;
  const float az_tol = V.az_tol, aa = azimuth[p];
  const auto joins = [lab, l, aa, azimuth, az_tol](std::uint32_t q, bool in, bool check_azimuth) {
    return in && lab[q] == l && (!check_azimuth || angDiff(aa, azimuth[q]) <= az_tol);  // Eq 19
  };
  // organized clouds: a column is one firing, beams may have their own azimuth offsets
  std::uint32_t q = uu;
  if (!joins(q, in0, !V.organized))
  {
    q = c1;
    if (!joins(q, in1, true))
    {
      q = c2;
      if (!joins(q, in2, true)) return p;
    }
  }
  const std::uint32_t rq = V.run[q];  // q has p's label: a run of its own
  if (rp != last_rp || rq != last_rq)
  {
    unite(V.parent, rp, rq);
    last_rp = rp;
    last_rq = rq;
  }
  // The next positions of the same run whose candidates all lie in rq's run (no seam
  // between them) can only unite what is united now: skip them untested. Runs are
  // contiguous: u-1, u, u+1 lie in rq's [qb, qe) when qb + 1 <= u <= qe - 2 (then also
  // b < u and u + 1 < e): one compare a position, where reading run[] at u - 1 and u + 1
  // took two loads and four tests.
  const std::uint32_t qb = V.runs[rq].begin, qe = V.runs[rq].end;
  if (qe - qb >= 3)
  {
    const std::uint32_t u_lo = qb + 1, span = qe - qb - 3;
    while (p + 1 < pe && static_cast<std::uint32_t>(V.up[p + 1]) - u_lo <= span) ++p;  // u = -1 wraps: out
  }
  return p;
}

// Vertical neighbours of ring n-1 (its runs [k0, k1)) in ring n [b, e): the nearest sample in
// azimuth, or one beside it, within Eq 19. Run by run: a position of an unwanted label has no
// run and is never visited, and a run's id, end and label are known without a look-up per
// position. Neighbouring runs meet many times over: the last pair of runs united is
// remembered, and the same pair again needs no find(). (none: no run has that id.) This is the
// baseline code; with AVX2 verticalUnionsAvx2 (below) runs, with AVX-512 verticalPairsAvx512.
__attribute__((noinline)) void verticalUnions(const VerticalRing& V, std::uint32_t k0, std::uint32_t k1,
                                              std::uint32_t none)
{
  std::uint32_t last_rp = none, last_rq = none;
  const D4 half_ratio = D4{0, 0, 0, 0} + V.half_ratio, min4 = D4{0, 0, 0, 0} + V.range_min;
  const I4 abs_mask = I4{0, 0, 0, 0} + 0x7fffffffffffffffLL;
  for (std::uint32_t rp = k0; rp < k1; ++rp)
  {
    const std::uint32_t pe = V.runs[rp].end;
    const Label l = V.lab[V.runs[rp].begin];
    for (std::uint32_t p = V.runs[rp].begin; p < pe; ++p)
    {
      if (V.up[p] < 0) continue;
      const auto uu = static_cast<std::uint32_t>(V.up[p]);
      const double ra = V.range[p];
      const std::uint32_t c1 = uu > V.b ? uu - 1 : V.e - 1, c2 = uu + 1 < V.e ? uu + 1 : V.b;
      // Most positions that find no candidate fail on the range for all three (the ground,
      // ring to ring): the three range tests first, without branches, and the label and
      // azimuth tests in order only where one passes.
      // (Eq 20 for the three in one vector, lane by lane the operations of inRange: fabs as a
      // cleared sign bit, std::max(t, min) as t < min ? min : t.)
      const D4 rb = D4{V.range[uu], V.range[c1], V.range[c2], V.range[c2]}, ra4 = D4{ra, ra, ra, ra};
      const D4 t = half_ratio * (ra4 + rb);
      const D4 tol = t < min4 ? min4 : t;
      const D4 dist = reinterpret_cast<D4>(reinterpret_cast<I4>(ra4 - rb) & abs_mask);
      const I4 out = dist > tol;  // -1 where out of range
      if ((out[0] & out[1] & out[2]) != 0) continue;
      p = joinAbove(V, rp, l, p, pe, uu, c1, c2, out[0] == 0, out[1] == 0, out[2] == 0, last_rp, last_rq);
    }
  }
}

#if defined(RC_SIMD_CLONES_ON)
// verticalUnions with AVX2 intrinsics: the same tests, lane by lane, in fewer operations. Off the
// seam (uu - 1 and uu + 1 in the ring) the three candidates' ranges are one unaligned load
// (lanes uu - 1, uu, uu + 1 and one unused), where building the vector of three took two loads
// and two shuffles more; the three verdicts are one move mask, where the generic vector code
// moved them out lane by lane (four more operations, two of them shuffles). Most visited
// positions stop there (all three out of range), so their cost is mostly these operations.
// Aligned to 64 bytes: where the code before it shrank by 16 bytes (duplicateSlots, one store
// less), its loops moved with it, and the stage took 1.011-1.014 of its time on KITTI with the
// code in this function unchanged; aligned, 0.994-0.997.
__attribute__((target("avx2"), noinline, aligned(64))) void verticalUnionsAvx2(const VerticalRing& V,
                                                                              std::uint32_t k0, std::uint32_t k1,
                                                                              std::uint32_t none)
{
  // (inRange's operations: fabs as a cleared sign bit, t < min ? min : t as max(min, t))
  const __m256d half4 = _mm256_set1_pd(V.half_ratio), min4 = _mm256_set1_pd(V.range_min);
  const __m256d abs_mask = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
  const std::uint32_t b = V.b, e = V.e;
  const std::int32_t* const up = V.up;
  const double* const range = V.range;
  std::uint32_t last_rp = none, last_rq = none;
  for (std::uint32_t rp = k0; rp < k1; ++rp)
  {
    const std::uint32_t pe = V.runs[rp].end;
    const Label l = V.lab[V.runs[rp].begin];
    for (std::uint32_t p = V.runs[rp].begin; p < pe; ++p)
    {
      if (up[p] < 0) continue;
      const auto uu = static_cast<std::uint32_t>(up[p]);
      const std::uint32_t c1 = uu > b ? uu - 1 : e - 1, c2 = uu + 1 < e ? uu + 1 : b;
      // lanes (c1, uu, c2, -)
      const __m256d rb = uu > b && uu + 2 < e ? _mm256_loadu_pd(range + uu - 1)
                                              : _mm256_setr_pd(range[c1], range[uu], range[c2], range[c2]);
      const __m256d ra = _mm256_broadcast_sd(range + p);
      const __m256d t = _mm256_mul_pd(half4, _mm256_add_pd(ra, rb));
      const __m256d tol = _mm256_max_pd(min4, t);
      const __m256d dist = _mm256_and_pd(_mm256_sub_pd(ra, rb), abs_mask);
      const int out = _mm256_movemask_pd(_mm256_cmp_pd(dist, tol, _CMP_GT_OQ));
      if ((out & 7) == 7) continue;
      p = joinAbove(V, rp, l, p, pe, uu, c1, c2, (out & 2) == 0, (out & 1) == 0, (out & 4) == 0, last_rp, last_rq);
    }
  }
}
#endif

// The duplicates' indices into their slots: `first` (at their roots) plus rank. Where no
// primitive is (comp -1, or an unwanted label's run: negative, both at least `total` as
// unsigned) the slot is `total`, one past the indices, which the caller drops: one store a
// duplicate either way, where a branch on the component was mispredicted about one time in 15
// (callgrind). A duplicate's slot gets no grid position (slot_pos): the sums weight its
// representative instead of reading it. (A function of its own: see the loops over a ring above.)
__attribute__((noinline)) void duplicateSlots(const std::uint32_t* __restrict dups, std::size_t num_dups,
                                              const std::int32_t* __restrict first,
                                              const std::uint32_t* __restrict dup_root,
                                              const std::uint32_t* __restrict dup_rank, std::uint32_t total,
                                              std::uint32_t* __restrict indices)
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
  // indices and of_grid: every entry is written below, so neither is cleared: a resize then
  // fills only what exceeds last frame's size (after a clear, resize zero-filled every index)
  out.of_grid.resize(m);
  // at most one run per position; num_runs counts the ones in use. Id m (none): the unwanted
  // labels' positions, one more entry in parent and comp.
  parent_.resize(m + 1);
  run_.resize(m + 16);  // (cutRingAvx512 writes up to 15 entries past a ring, reads join 16 past it)
  runs_.resize(m);
  comp_.resize(m + 1);
  roots_.resize(m);
  grid_size_.resize(m);
  join_.resize(m + 16);
  run_begins_.resize(m + 16);
  run_ends_.resize(m + 16);
  vertical_pairs_.resize(m + 8);

  // a table: this is asked once or more per grid position in every loop below. Lambdas in the
  // loops capture by value: through a reference capture the compiler read the captured locals
  // back from memory after stores it could not prove unrelated (-5 % each on KITTI).
  const bool want[kNumLabels] = {false, true, true, true, P.rough_primitives};
  static_assert(static_cast<int>(Label::Plane) == 1 && static_cast<int>(Label::Edge) == 2 &&
                    static_cast<int>(Label::Corner) == 3 && static_cast<int>(Label::Rough) == 4,
                "want[] is indexed by Label");
  const auto wanted = [want](Label l) { return want[static_cast<std::size_t>(l)]; };
  const float az_tol = P.proximity_azimuth_factor * g.azimuth_resolution;  // Eq 19
  const std::uint8_t num_wanted = P.rough_primitives ? 4 : 3;  // want[] as a range: labels 1 to num_wanted
  // Raw pointers and parameters in locals, read once: through the vectors and P the compiler
  // reloaded data pointers and parameters inside the loops below (perf annotate), as it may not
  // prove that the stores to parent_ / the primitives leave them unchanged.
  const std::uint32_t* const ring_begin = g.ring_begin.data();
  const double* const range = g.range.data();
  const float* const azimuth = g.azimuth.data();
  const Label* const lab = labels.data();
  const std::uint8_t* const linked = g.linked.data();
  const std::int32_t* const up = g.up.empty() ? nullptr : g.up.data();
  const std::int32_t* const grid_pos = g.grid_pos.data();
  const bool organized = g.organized;
  const double range_ratio = P.proximity_range_ratio;
  const double range_min = static_cast<double>(P.proximity_range_min);
  // Proximity of a pair from its ranges and azimuths, in the original order of the operands.
  // Values rather than positions: the loops below keep one side in registers.
  const auto close = [range_ratio, range_min, az_tol](double ra, float aa, double rb, float ab, bool check_azimuth) {
    return inRange(ra, rb, range_ratio, range_min) && (!check_azimuth || angDiff(aa, ab) <= az_tol);  // Eq 19
  };

  // Unions. Most angular neighbours unite, so each ring is first cut into runs (see Run): a
  // position joins its predecessor's run with a store instead of two find() calls. Only the
  // runs (by id, see cutRing) enter the union-find forest. Ring n is cut before the vertical
  // unions of ring n-1 reach into it (up[] of ring n-1 points into ring n).
  std::uint32_t* const parent = parent_.data();
  std::uint32_t* const run = run_.data();
  std::int32_t* const comp = comp_.data();
  Run* const runs = runs_.data();
  std::uint8_t* const join = join_.data();
  const auto none = static_cast<std::uint32_t>(m);
  parent[none] = none;
#if defined(RC_SIMD_CLONES_ON)
  const bool avx2 = __builtin_cpu_supports("avx2");
  const bool avx512 = detail::avx512Forms() && __builtin_cpu_supports("popcnt");
  const bool vertical_pairs = verticalPairsRuns();
  std::uint64_t* const pairs = vertical_pairs_.data();
#endif
  // A component's size is counted at its root. A duplicate of an unwanted label's position
  // counts at `none`, which starts far below zero: it counts without a test and its component
  // reads as rejected (negative).
  comp[none] = std::numeric_limits<std::int32_t>::min();
  std::size_t num_runs = 0, ring_runs = 0;  // ring_runs: the first run of ring n-1
  for (int n = 0; n < g.num_rings; ++n)
  {
    const std::uint32_t b = ring_begin[n], e = ring_begin[n + 1];
    const std::size_t first_run = num_runs;
    if (b < e)
    {
      angularJoins(b, e, lab, linked, range, azimuth, num_wanted, range_ratio, range_min, az_tol, join);
#if defined(RC_SIMD_CLONES_ON)
      if (avx512)
        num_runs = cutRingAvx512(b, e, lab, join, num_wanted, none, parent, run, comp, runs, num_runs,
                                 run_begins_.data(), run_ends_.data());
      else if (avx2)
        num_runs = cutRingAvx2(b, e, lab, join, num_wanted, none, parent, run, comp, runs, num_runs,
                               run_begins_.data(), run_ends_.data());
      else
#endif
        num_runs = cutRing(b, e, lab, join, want, none, parent, run, comp, runs, num_runs);
    }
    // the seam: (n, K-1) and (n, 0); the ring's runs are all roots still
    if (e - b >= 2)
    {
      const Label l = lab[e - 1];
      if (wanted(l) && linked[b] && lab[b] == l && close(range[e - 1], azimuth[e - 1], range[b], azimuth[b], true))
        parent[run[e - 1]] = run[b];
    }
    if (n > 0 && up != nullptr)
    {
      const VerticalRing V{b, e, runs, lab, up, range, azimuth, organized, range_ratio * 0.5, range_min, az_tol,
                           run, parent};
      const auto k0 = static_cast<std::uint32_t>(ring_runs), k1 = static_cast<std::uint32_t>(first_run);
#if defined(RC_SIMD_CLONES_ON)
      if (vertical_pairs)
      {
        // The same unions as the loops' in another order: the components and their roots (the
        // smallest run id) do not depend on it. Consecutive entries differ: the test asks only
        // across a position without a pair.
        const std::size_t np = verticalPairsAvx512(V, ring_begin[n - 1], b, none, pairs);
        std::uint64_t last = kNoVerticalPair;
        for (std::size_t i = 0; i < np; ++i)
          if (pairs[i] != last)
          {
            last = pairs[i];
            unite(parent, static_cast<std::uint32_t>(last), static_cast<std::uint32_t>(last >> 32));
          }
      }
      else if (avx2)
        verticalUnionsAvx2(V, k0, k1, none);
      else
#endif
        verticalUnions(V, k0, k1, none);
    }
    ring_runs = first_run;
  }

  // Component sizes, run by run. A root is the smallest run id of its component (see unite),
  // so it is the component's first run, and path halving keeps parent[k] <= k: in grid
  // order, parent[parent[k]] is already the root, and is stored back for the look-ups below.
  // Roots are listed as they come, i.e. in scan order. Each run and each duplicate keeps its
  // rank among the points of its component (the count before it), which is where its indices
  // go: the fill below then needs no cursor per primitive.
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
  std::uint32_t* const grid_size = grid_size_.data();
  for (std::size_t k = 0; k < num_roots; ++k) grid_size[k] = static_cast<std::uint32_t>(comp[roots[k]]);
  // duplicates (same firing, same range) join their representative's primitive, after its
  // grid points, in input order; and count at their representative's grid position, whose
  // weight in the sums they are (primitive_sums.cpp). The counts are uint32: a position has
  // fewer duplicates than the cloud has points, whose indices are uint32.
  const std::uint32_t* const dups = g.duplicates.data();
  const std::size_t num_dups = g.duplicates.size();
  dup_root_.resize(num_dups);
  dup_rank_.resize(num_dups);
  std::uint32_t* const dup_root = dup_root_.data();
  std::uint32_t* const dup_rank = dup_rank_.data();
  // dup_count_ is zero between frames (cleared after the sums, below; a resize zero-fills new
  // entries), so that a frame with a few duplicates clears only their entries, not the grid's:
  // a memset of the grid's counts on each frame with duplicates took the stage 1.004-1.022 of
  // this one's time on the 14.7k last-return frames (20-30 duplicates a frame). (If an exception
  // left it dirty, e.g. bad_alloc below, it is cleared in full first.)
  std::uint32_t* dup_count = nullptr;
  if (num_dups > 0)
  {
    dup_count_.resize(m);
    dup_count = dup_count_.data();
    if (!dup_count_zero_) std::memset(dup_count, 0, m * sizeof *dup_count);
    dup_count_zero_ = false;
  }
  for (std::size_t k = 0; k < num_dups; ++k)
  {
    const auto pos = static_cast<std::size_t>(grid_pos[dups[k]]);
    ++dup_count[pos];
    const std::uint32_t r = parent[run[pos]];  // an unwanted label's position: none, comp[r] stays negative
    dup_root[k] = r;
    dup_rank[k] = static_cast<std::uint32_t>(comp[r]++);
  }
  // ids for the large-enough components, in scan order; comp becomes the id at each root, and
  // grid_size is compacted to be indexed by id
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
    prim.label = lab[runs[r].begin];
    prim.first = total;
    prim.num_points = size;
    total += size;
    comp[r] = static_cast<std::int32_t>(prim.id);
    roots[prim.id] = r;  // the roots of the primitives, by id (prim.id <= k: read already)
    grid_size[prim.id] = grid_size[k];
    out.primitives.push_back(prim);
  }
  // not cleared above: see of_grid. One more entry: the rejected duplicates' (see below).
  out.indices.resize(std::size_t{total} + 1);

  // Indices, run by run: a run is a block of consecutive positions and input indices. Each grid
  // point's entry of `indices` also gets its grid position (slot_pos_), so that the sums below
  // walk a primitive's grid points in the order of its indices with sequential reads and register
  // sums.
  slot_pos_.resize(std::size_t{total} + 1);
  PrimitiveInfo* const prims = out.primitives.data();
  std::uint32_t* const indices = out.indices.data();
  std::uint32_t* const slot_pos = slot_pos_.data();
  std::int32_t* const of_grid = out.of_grid.data();
  const std::uint32_t* const index = g.index.data();
  const double* const gx = g.x.data();
  const double* const gy = g.y.data();
  const double* const gz = g.z.data();
#if defined(RC_SIMD_CLONES_ON)
  // (its masked stores are slow on AMD: the stage took 1.14-1.19 times the plain loop's time there)
  if (detail::avx2Gathers())
    fillRunsAvx2(runs, num_runs, parent, comp, ring_begin, prims, index, indices, slot_pos, of_grid,
                 static_cast<std::uint32_t>(m));
  else
#endif
  {
    using U4 = std::uint32_t __attribute__((vector_size(16)));
    int n = 0;
    // of_grid is written once, the gaps before each reported run with -1: filling all of it
    // with -1 first was 6 % slower on the 120k-point clouds
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
      // Four positions a step, the last step ending at the run's end (overlapping the one
      // before: it writes the same values again). One scalar position a step was bound by its
      // three stores; the compiler's own vectorized loop cost more than it saved on short runs.
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
  }
  // Duplicates into their slots: comp becomes the first slot at each primitive's root
  for (std::size_t id = 0; id < out.primitives.size(); ++id)
    comp[roots[id]] = static_cast<std::int32_t>(prims[id].first);
  duplicateSlots(dups, num_dups, comp, dup_root, dup_rank, total, indices);
  out.indices.resize(total);

  // Box, centroid, moments and axes, primitive by primitive (primitive_sums.cpp for the sums, one
  // pass in double over the grid points, each weighted by its duplicates: the covariance is about
  // the mean, the centroid that mean rounded to float)
  for (auto& pr : out.primitives)
  {
    PrimitiveSums S;
    primitiveSums(slot_pos + pr.first, grid_size[pr.id], pr.num_points, dup_count, gx, gy, gz, S);
    pr.bbox_min = Eigen::Vector3f(S.lo[0], S.lo[1], S.lo[2]);
    pr.bbox_max = Eigen::Vector3f(S.hi[0], S.hi[1], S.hi[2]);
    pr.centroid = Eigen::Vector3f(S.centroid[0], S.centroid[1], S.centroid[2]);
    const Eigen::Vector3d c = pr.centroid.cast<double>();
    const std::uint32_t np = pr.num_points;
    Eigen::Matrix3d cov;
    cov << S.m[0], S.mxy[0], S.m[2], S.mxy[0], S.m[1], S.mxy[1], S.m[2], S.mxy[1], S.m[3];
    cov /= static_cast<double>(np);
    pr.covariance = cov.cast<float>();
    Eigen::Vector3d eigenvalues, axis;  // (covariance_axis.hpp: computeDirect's steps, one column)
    covarianceAxis(cov, pr.label == Label::Plane ? 0 : 2, eigenvalues, axis);
    const Eigen::Vector3d ev = eigenvalues.cwiseMax(0.0);  // ascending
    pr.eigenvalues = ev.cast<float>();
    if (pr.label == Label::Plane)
    {
      if (axis.dot(c) > 0) axis = -axis;  // face the sensor
      pr.axis = axis.cast<float>();
      pr.rms_error = static_cast<float>(std::sqrt(ev(0)));
    }
    else
    {
      pr.axis = axis.cast<float>();
      pr.rms_error = static_cast<float>(std::sqrt(ev(0) + ev(1)));
    }
  }
  // the counts back to zero: the duplicates' entries one by one where they are few (the 14.7k
  // last-return frames: 20-30 among 14.6k positions), else the whole array (the dual-return
  // frames: a duplicate for nearly every position, and a memset is a fraction of a pass)
  if (num_dups > 0)
  {
    if (num_dups * 16 < m)
      for (std::size_t k = 0; k < num_dups; ++k) dup_count[grid_pos[dups[k]]] = 0;
    else
      std::memset(dup_count, 0, m * sizeof *dup_count);
    dup_count_zero_ = true;
  }
}

}  // namespace ring_curvature
