// Box, centroid and second moments of one primitive (see primitive_sums.hpp).
#include "primitive_sums.hpp"

#include <cstring>
#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>
#endif

namespace ring_curvature
{

// Box, centroid and second moments of one primitive from the grid positions of its points, in
// the order of its indices (grid points first, then duplicates), in one pass over them. The
// first point's coordinates are the reference r; each point p adds, in double, d = p - r, its
// squares d d and its cross products d rot(d), rot(d) = (dy, dz, dx), and a grid point p
// goes to the box's min and max (a duplicate repeats an earlier point, so it would leave the box
// as it is and goes to the sums only). finishSums then takes the mean as r + sum(d) / n and the
// moments about it as sum(d d^T) - sum(d) sum(d)^T / n.
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
//   each (GCC vector extensions in the baseline form, two SSE2 halves; intrinsics with AVX2),
//   each lane the same subtraction, product, sum, min and max as the scalar definition. The
//   first point adds d = 0 (+0 to sums that are +0), so the loops start at the second.
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

// The outputs from the pass's sums, the same code after either form. Inlined: called from the
// AVX2 form, it ran as SSE code with the upper halves of the vector registers dirty (GCC put no
// vzeroupper before the call), and with them the rest of the stage: primitives 1.48.
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
void primitiveSumsPlain(const std::uint32_t* __restrict sp, std::uint32_t ng, std::uint32_t np,
                        const double* __restrict gx, const double* __restrict gy, const double* __restrict gz,
                        PrimitiveSums& out)
{
  // (a macro: a lambda returning a 32-byte vector changes the ABI without AVX, -Wpsabi)
#define RC_XYZZ(p) (D4{gx[p], gy[p], gz[p], gz[p]})
  const D4 r = RC_XYZZ(sp[0]);
  D4 lo = r, hi = r, s = D4{0, 0, 0, 0}, dd = s, dr = s;
  const auto add = [&r, &s, &dd, &dr](const D4& p) {
    const D4 d = p - r;  // (dx, dy, dz, dz)
    s += d;
    dd += d * d;
    dr += d * __builtin_shufflevector(d, d, 1, 2, 0, 0);
  };
  for (std::uint32_t k = 1; k < ng; ++k)
  {
    const D4 p = RC_XYZZ(sp[k]);
    lo = p < lo ? p : lo;  // std::min(lo, p), lane by lane
    hi = hi < p ? p : hi;  // std::max(hi, p)
    add(p);
  }
  for (std::uint32_t k = ng; k < np; ++k) add(RC_XYZZ(sp[k]));  // duplicates
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

#if defined(RC_SIMD_CLONES_ON)
// primitiveSumsPlain with AVX2 intrinsics, the same operations lane by lane (so the same bits),
// in another data flow: a point's coordinates are three broadcast loads, and its vector is made
// of them by blends. Gathered into a vector by inserts and shuffles (the plain form's data flow,
// which its AVX2 target clone had too), a point took three shuffles, all on the one port that
// shuffles 256-bit vectors; blends run on any of three ports, and a broadcast is a load alone.
// rot(d) is one lane-crossing permutation a point: (dx, dy, dz, dz) times (dx, dy, dx, dz) and
// (dx, dy) times (dy, dz), each pair built by blends and subtractions, took 3 more operations a
// point, and the operations on the three vector ports, not the additions' latency, bound it.
namespace
{
// (x, y, z, z) of position p from three broadcasts
__attribute__((target("avx2"))) inline __m256d xyzzAvx2(const double* gx, const double* gy, const double* gz,
                                                       std::uint32_t p)
{
  const __m256d xy = _mm256_blend_pd(_mm256_broadcast_sd(gx + p), _mm256_broadcast_sd(gy + p), 0b0010);
  return _mm256_blend_pd(xy, _mm256_broadcast_sd(gz + p), 0b1100);
}
__attribute__((target("avx2"))) inline void addAvx2(__m256d p, __m256d r, __m256d& s, __m256d& dd, __m256d& dr)
{
  const __m256d d = _mm256_sub_pd(p, r);  // (dx, dy, dz, dz)
  s = _mm256_add_pd(s, d);
  dd = _mm256_add_pd(dd, _mm256_mul_pd(d, d));
  dr = _mm256_add_pd(dr, _mm256_mul_pd(d, _mm256_permute4x64_pd(d, 0x09)));  // d (dy, dz, dx, dx)
}
}  // namespace

__attribute__((target("avx2"))) void primitiveSumsAvx2(const std::uint32_t* __restrict sp, std::uint32_t ng,
                                                       std::uint32_t np, const double* __restrict gx,
                                                       const double* __restrict gy, const double* __restrict gz,
                                                       PrimitiveSums& out)
{
  const __m256d r = xyzzAvx2(gx, gy, gz, sp[0]);
  __m256d lo = r, hi = r, s = _mm256_setzero_pd(), dd = s, dr = s;
  for (std::uint32_t k = 1; k < ng; ++k)
  {
    const __m256d p = xyzzAvx2(gx, gy, gz, sp[k]);
    lo = _mm256_min_pd(p, lo);  // p < lo ? p : lo, as std::min(lo, p)
    hi = _mm256_max_pd(p, hi);  // p > hi ? p : hi, as std::max(hi, p)
    addAvx2(p, r, s, dd, dr);
  }
  for (std::uint32_t k = ng; k < np; ++k) addAvx2(xyzzAvx2(gx, gy, gz, sp[k]), r, s, dd, dr);  // duplicates
  OnePass a;
  _mm256_store_pd(a.r, r);
  _mm256_store_pd(a.lo, lo);
  _mm256_store_pd(a.hi, hi);
  _mm256_store_pd(a.s, s);
  _mm256_store_pd(a.dd, dd);
  _mm256_store_pd(a.dr, dr);
  finishSums(a, np, out);
}
#endif

void primitiveSums(const std::uint32_t* sp, std::uint32_t ng, std::uint32_t np, const double* gx, const double* gy,
                   const double* gz, PrimitiveSums& out)
{
#if defined(RC_SIMD_CLONES_ON)
  if (__builtin_cpu_supports("avx2"))
  {
    primitiveSumsAvx2(sp, ng, np, gx, gy, gz, out);
    return;
  }
#endif
  primitiveSumsPlain(sp, ng, np, gx, gy, gz, out);
}

}  // namespace ring_curvature
