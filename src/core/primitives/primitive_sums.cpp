// Box, centroid and second moments of one primitive (see primitive_sums.hpp).
#include "primitives/primitive_sums.hpp"

#include <algorithm>
#include <cstring>

namespace ring_curvature
{

// One pass: with r the first point and d = p - r, each grid point of weight w adds in double w d,
// (w d) d and (w d) rot(d), rot(d) = (dy, dz, dx); the mean is r + sum(w d) / n, the moments
// sum(w d d^T) - sum(w d) sum(w d)^T / n (only the six distinct ones), n counting duplicates.
// - A grid point with c duplicates stands for w = 1 + c points: w = 2 is an exact product, the
//   point's terms twice (w > 2 rounds once). One weighted loop serves all: 1 d is d exactly.
// - Precision: double sums about a point of the primitive, so |d| is at most its extent and the
//   cancellation is a two-pass sum's (about the origin, n 6400 m^2 against cm^2 would cancel all).
// - The box in double, converted once: rounding to float is monotonic, so it equals min / max of
//   the floats bit for bit but for a zero's sign (a coordinate within 2^-150 of 0; never a float's).
// - Lanes (x, y, z, z) do the scalar operations; the first point adds d = 0, so loops skip it.
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
  const auto addWeighted = [&r, &s, &dd, &dr](const D4& p, std::uint32_t c) {
    const double w = 1.0 + static_cast<double>(c);  // exact: c < 2^32
    const D4 d = p - r, wd = D4{w, w, w, w} * d;
    s += wd;
    dd += wd * d;
    dr += wd * __builtin_shufflevector(d, d, 1, 2, 0, 0);
  };
  for (std::uint32_t k = 1; k < ng; ++k)
  {
    const D4 p = RC_XYZZ(sp[k]);
    box(p);
    addWeighted(p, np == ng ? 0u : dup_count[sp[k]]);
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
