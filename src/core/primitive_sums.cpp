// Box, centroid and second moments of one primitive (see primitive_sums.hpp).
#include "primitive_sums.hpp"

#include <algorithm>
#include <cstring>
#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>
#endif

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
//   more, after the grid points: on the dual-return frames about half the points are
//   duplicates, and the sums did about twice the work (without the duplicates' terms the stage
//   took 0.883 of its time, session 8). The product by w = 2 is exact, so the terms are those of
//   the point added twice and the sums differ only in the order of the additions (w > 2, more
//   identical returns of one firing, rounds w d once): a decided change of the primitives' last
//   bits. A primitive without duplicates (every one on a single-return frame) keeps the
//   unweighted loop: the same bits as before and no more work.
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
//   first point adds d = 0, times any w (+0 to sums that are +0), so the loops start at the
//   second.
// - The weighted loop weights every grid point, c = 0 included (1 d is d exactly: the
//   unweighted terms). A loop with a branch on c == 0 that skipped the weight in primitives with
//   few duplicates (the frames with a few identical returns, such as the 14.7k last-return
//   fixture, 20-30 a frame) gained nothing measurable there (primitives 0.990-1.014 without
//   it, median 1.003, eight runs).
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
// Asks, every fourth grid point, for the lines of the point 64 places ahead in the list (or of
// its last point). A primitive's runs lie on different rings, far apart in the grid's arrays, so
// the hardware's stream prefetch misses each run's first lines, and the loop waited on its
// broadcast loads (a fifth of its samples on the first one). Primitives 0.957 on KITTI, 0.965
// on the OS1-128 frames, 0.986 on the 29k ones (ab_core); 32 ahead 0.980 on KITTI, 128 ahead or
// every eighth point no better. always_inline: merely inline, GCC dropped the prefetches.
__attribute__((target("avx2"), always_inline)) inline void prefetchAhead(const std::uint32_t* sp, std::uint32_t k,
                                                                         std::uint32_t ng, const double* gx,
                                                                         const double* gy, const double* gz)
{
  if ((k & 3) != 0) return;
  const std::uint32_t a = sp[std::min(k + 64, ng - 1)];
  __builtin_prefetch(gx + a);
  __builtin_prefetch(gy + a);
  __builtin_prefetch(gz + a);
}
// d = p - r and its terms d, d d and d rot(d) into the sums
__attribute__((target("avx2"))) inline void addAvx2(__m256d p, __m256d r, __m256d& s, __m256d& dd, __m256d& dr)
{
  const __m256d d = _mm256_sub_pd(p, r);  // (dx, dy, dz, dz)
  s = _mm256_add_pd(s, d);
  dd = _mm256_add_pd(dd, _mm256_mul_pd(d, d));
  dr = _mm256_add_pd(dr, _mm256_mul_pd(d, _mm256_permute4x64_pd(d, 0x09)));  // d (dy, dz, dx, dx)
}
// the same, weighted: w d, (w d) d and (w d) rot(d)
__attribute__((target("avx2"))) inline void addWeightedAvx2(__m256d p, __m256d w, __m256d r, __m256d& s,
                                                            __m256d& dd, __m256d& dr)
{
  const __m256d d = _mm256_sub_pd(p, r), wd = _mm256_mul_pd(w, d);
  s = _mm256_add_pd(s, wd);
  dd = _mm256_add_pd(dd, _mm256_mul_pd(wd, d));
  dr = _mm256_add_pd(dr, _mm256_mul_pd(wd, _mm256_permute4x64_pd(d, 0x09)));
}
// w = 1 + c in every lane, the double 1.0 + c (exact): c as the low bits of the double 2^52 + c,
// minus 2^52 - 1. A 32-bit broadcast load, a blend (any of three ports) and a subtraction, where
// converting c (cvtsi2sd) and broadcasting the double put two more operations on the port that
// shuffles (primitives 0.983 against 0.974 of main's time on the 29k frames, one run each).
// Tried besides: the counts as doubles, a broadcast load and an addition (their array twice the
// size: primitives 1.016-1.022 of this form's time, three runs); weights as doubles filled with
// 1.0, a broadcast load alone (1.015); a table of 1 + c for c < 8 behind a branch (0.985-1.011).
__attribute__((target("avx2"))) inline __m256d weightAvx2(std::uint32_t c)
{
  const __m256i bits = _mm256_blend_epi32(_mm256_set1_epi32(static_cast<int>(c)),
                                          _mm256_set1_epi64x(0x4330000000000000LL), 0b10101010);
  return _mm256_sub_pd(_mm256_castsi256_pd(bits), _mm256_set1_pd(4503599627370495.0));
}
}  // namespace

__attribute__((target("avx2"))) void primitiveSumsAvx2(const std::uint32_t* __restrict sp, std::uint32_t ng,
                                                       std::uint32_t np, const std::uint32_t* __restrict dup_count,
                                                       const double* __restrict gx, const double* __restrict gy,
                                                       const double* __restrict gz, PrimitiveSums& out)
{
  const __m256d r = xyzzAvx2(gx, gy, gz, sp[0]);
  __m256d lo = r, hi = r, s = _mm256_setzero_pd(), dd = s, dr = s;
  if (np == ng)
  {
    for (std::uint32_t k = 1; k < ng; ++k)
    {
      prefetchAhead(sp, k, ng, gx, gy, gz);
      const __m256d p = xyzzAvx2(gx, gy, gz, sp[k]);
      lo = _mm256_min_pd(p, lo);  // p < lo ? p : lo, as std::min(lo, p)
      hi = _mm256_max_pd(p, hi);  // p > hi ? p : hi, as std::max(hi, p)
      addAvx2(p, r, s, dd, dr);
    }
  }
  else
  {
    for (std::uint32_t k = 1; k < ng; ++k)
    {
      prefetchAhead(sp, k, ng, gx, gy, gz);
      const __m256d p = xyzzAvx2(gx, gy, gz, sp[k]);
      lo = _mm256_min_pd(p, lo);
      hi = _mm256_max_pd(p, hi);
      addWeightedAvx2(p, weightAvx2(dup_count[sp[k]]), r, s, dd, dr);
    }
  }
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

void primitiveSums(const std::uint32_t* sp, std::uint32_t ng, std::uint32_t np, const std::uint32_t* dup_count,
                   const double* gx, const double* gy, const double* gz, PrimitiveSums& out)
{
#if defined(RC_SIMD_CLONES_ON)
  if (__builtin_cpu_supports("avx2"))
  {
    primitiveSumsAvx2(sp, ng, np, dup_count, gx, gy, gz, out);
    return;
  }
#endif
  primitiveSumsPlain(sp, ng, np, dup_count, gx, gy, gz, out);
}

}  // namespace ring_curvature
