// Box, centroid and second moments of one primitive (see primitive_sums.hpp).
#include "primitives/primitive_sums.hpp"

#include <algorithm>
#include <cstring>

namespace ring_curvature
{

// Box, centroid and second moments of one primitive from the grid positions of its grid points,
// in the order of its indices, in one pass over them. The first point's coordinates are the
// reference r; each grid point p, of weight w (below: 1 in a primitive without duplicates),
// adds in double w d, (w d) d and (w d) rot(d), d = p - r, rot(d) = (dy, dz, dx), and goes to
// the box's min and max. finishSums then takes the mean as r + sum(w d) / n and the moments
// about it as sum(w d d^T) - sum(w d) sum(w d)^T / n, n the primitive's points, duplicates
// included.
// - Duplicates (dual return: the second return of a firing at the first one's range) are their
//   representative's point again. A grid point with c of them (counted per grid position by
//   extract) stands for w = 1 + c points. Each duplicate added its representative's terms once
//   more would do the sums' work twice on dual-return frames, where about half the points are
//   duplicates. The product by w = 2 is exact, so the terms are those of the point added twice
//   (w > 2, more identical returns of one firing, rounds w d once). A primitive without
//   duplicates (every one on a single-return frame) takes the unweighted loop.
// - Why one pass: the box and a float centroid came first and the moments about that centroid
//   second, which read every point's coordinates twice; the first pass waited on their loads.
// - Accuracy: that centroid was a float sum (80 m away, floats are 4-8 um apart, and the sum's
//   rounding grows with the points), and moments about a centroid off by e carry n e e^T more
//   than those about the mean. Here every sum is double and the moments are about the mean
//   itself (core_test_primitive_sums holds both schemes to a long double two-pass reference).
// - Cancellation: r is one of the points, so each |d| is at most the primitive's extent along
//   its axis, as are sum(d) / n and the two-pass scheme's differences from the mean; the terms
//   subtracted are no larger than n extent^2, so the rounding is that of a two-pass sum with
//   differences of the primitive's size. (About the origin instead, 80 m away, the terms would
//   be n 6400 m^2 against a spread of cm^2: all the digits would cancel.)
// - The box in double, converted once at the end: rounding to float is monotonic, so the float
//   of the least double is the least of the floats, the same box as min / max of the points'
//   floats (as before) but one conversion a primitive instead of one a point. The bits match
//   too, ties included (both keep the earlier point), except for a zero's sign where a nonzero
//   coordinate within 2^-150 of 0 rounds to a float zero (never a float's coordinate).
// - Lanes (x, y, z, z): a point's coordinates, d, the sums and the box are one double vector
//   each (GCC vector extensions: one AVX2 vector in the AVX2 clone, two halves elsewhere), each
//   lane the same subtraction, product, sum, min and max as the scalar definition. The first
//   point adds d = 0, times any w (+0 to sums that are +0), so the loops start at the second.
// - The weighted loop weights every grid point, c = 0 included (1 d is d exactly: the
//   unweighted terms), without a branch on c.
// - The six distinct moments only: d d^T is symmetric (d_i d_j and d_j d_i are the same double),
//   so extract fills the matrix from them once per primitive.
namespace
{
// The pass's sums, lanes (x, y, z, z): r, the box, sum(d), d d = (xx, yy, zz, zz) and
// d rot(d) = (xy, yz, zx, zx), stored from the vectors (whose layout is that of the arrays).
struct OnePass
{
  alignas(32) double r[4], lo[4], hi[4], s[4], dd[4], dr[4];
};

// The outputs from the pass's sums. Inlined, so that it runs in the caller's clone (a baseline
// call from the AVX2 clone would run with the vector registers' upper halves dirty).
__attribute__((always_inline)) inline void finishSums(const OnePass& a, std::uint32_t np, PrimitiveSums& out)
{
  const auto n = static_cast<double>(np);
  double mean[4];  // the mean's offset from r
  for (int i = 0; i < 4; ++i)
  {
    mean[i] = a.s[i] / n;
    out.lo[i] = static_cast<float>(a.lo[i]);
    out.hi[i] = static_cast<float>(a.hi[i]);
    out.centroid[i] = static_cast<float>(a.r[i] + mean[i]);
  }
  out.m[0] = a.dd[0] - a.s[0] * mean[0];  // xx
  out.m[1] = a.dd[1] - a.s[1] * mean[1];  // yy
  out.m[2] = a.dr[2] - a.s[2] * mean[0];  // zx
  out.m[3] = a.dd[2] - a.s[2] * mean[2];  // zz
  out.mxy[0] = a.dr[0] - a.s[0] * mean[1];  // xy
  out.mxy[1] = a.dr[1] - a.s[1] * mean[2];  // yz
}
}  // namespace

using D4 = double __attribute__((vector_size(32)));
RC_SIMD_CLONES void primitiveSums(const std::uint32_t* __restrict sp, std::uint32_t ng, std::uint32_t np,
                        const std::uint32_t* __restrict dup_count, const double* __restrict gx,
                        const double* __restrict gy, const double* __restrict gz, PrimitiveSums& out)
{
  // (a macro: a lambda returning a 32-byte vector changes the ABI without AVX, -Wpsabi)
#define RC_XYZZ(p) (D4{gx[p], gy[p], gz[p], gz[p]})
  const D4 r = RC_XYZZ(sp[0]);
  D4 lo = r, hi = r, s = D4{0, 0, 0, 0}, dd = s, dr = s;
  const auto box = [&lo, &hi](const D4& p) {
    lo = p < lo ? p : lo;  // std::min(lo, p), lane by lane
    hi = hi < p ? p : hi;  // std::max(hi, p)
  };
  const auto add = [&r, &s, &dd, &dr](const D4& p) {
    const D4 d = p - r;  // (dx, dy, dz, dz)
    s += d;
    dd += d * d;
    dr += d * __builtin_shufflevector(d, d, 1, 2, 0, 0);
  };
  const auto addWeighted = [&r, &s, &dd, &dr](const D4& p, std::uint32_t c) {
    const double w = 1.0 + static_cast<double>(c);  // exact: c < 2^32
    const D4 d = p - r, wd = D4{w, w, w, w} * d;
    s += wd;
    dd += wd * d;
    dr += wd * __builtin_shufflevector(d, d, 1, 2, 0, 0);
  };
  if (np == ng)
    for (std::uint32_t k = 1; k < ng; ++k)
    {
      const D4 p = RC_XYZZ(sp[k]);
      box(p);
      add(p);
    }
  else
    for (std::uint32_t k = 1; k < ng; ++k)
    {
      const D4 p = RC_XYZZ(sp[k]);
      box(p);
      addWeighted(p, dup_count[sp[k]]);
    }
#undef RC_XYZZ
  OnePass a;
  std::memcpy(a.r, &r, sizeof r);
  std::memcpy(a.lo, &lo, sizeof lo);
  std::memcpy(a.hi, &hi, sizeof hi);
  std::memcpy(a.s, &s, sizeof s);
  std::memcpy(a.dd, &dd, sizeof dd);
  std::memcpy(a.dr, &dr, sizeof dr);
  finishSums(a, np, out);
}

}  // namespace ring_curvature
