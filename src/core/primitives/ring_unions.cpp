// The union-find steps of the primitive extraction (see ring_unions.hpp): linear time, no recursion.
#include "primitives/ring_unions.hpp"

#include "primitives/proximity.hpp"
#include "common/simd_clones.hpp"

#include <algorithm>

namespace ring_curvature
{
namespace detail
{
namespace
{
// GCC vector types for the range tests of the vertical unions
using D4 = double __attribute__((vector_size(32)));
using I4 = long long __attribute__((vector_size(32)));

// Position p of run rp against uu (nearest above) and c1, c2 beside it (in0..in2: within Eq 20).
// Returns the last position covered: p, or beyond where later ones only unite what is united.
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
  // Later positions of the run whose candidates u-1, u, u+1 all lie in rq's run [qb, qe) (runs are
  // contiguous: qb + 1 <= u <= qe - 2) can only unite what is united now: skipped, one compare each.
  const std::uint32_t qb = V.runs[rq].begin, qe = V.runs[rq].end;
  if (qe - qb >= 3)
  {
    const std::uint32_t u_lo = qb + 1, span = qe - qb - 3;
    while (p + 1 < pe && static_cast<std::uint32_t>(V.up[p + 1]) - u_lo <= span) ++p;  // u = -1 wraps: out
  }
  return p;
}
}  // namespace

// Operands in the order of the pair (p-1, p); each position on its own, without branches, so that
// the loop vectorizes.
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

// The runs of wanted labels are listed and numbered in grid order: the union-find forest and the
// component counts are per run, dense arrays of a few thousand entries rather than grid-sized.
// Each run is its own root; positions of unwanted labels get the id `none`.
RC_SIMD_CLONES std::size_t cutRing(std::uint32_t b, std::uint32_t e, const Label* __restrict lab,
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
  // (a loop per run, so that the next run's entries are not prepared at every position)
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

// Vertical neighbours of ring n-1 (runs [k0, k1)) in ring n [b, e): the nearest sample in azimuth,
// or one beside it, within Eq 19. Run by run, so unwanted positions are never visited and a run's
// id, end and label need no look-up; the last pair united is remembered (`none`: no run's id).
RC_SIMD_CLONES void verticalUnions(const VerticalRing& V, std::uint32_t k0, std::uint32_t k1,
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
      // Most positions without a candidate fail on range for all three (the ground, ring to ring):
      // the three Eq 20 tests first, branch-free in one vector (lane by lane inRange's operations:
      // fabs as a cleared sign bit, std::max as t < min ? min : t), the others only if one passes.
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

}  // namespace detail
}  // namespace ring_curvature
