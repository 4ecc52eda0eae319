// Box, centroid and second moments of one primitive (see primitive_sums.hpp).
#include "primitive_sums.hpp"

#include "simd_clones.hpp"

#include <cstring>
#if defined(RC_SIMD_CLONES_ON)
#include <immintrin.h>
#endif

namespace ring_curvature
{

namespace
{
// Box, centroid and second moments of one primitive from the grid positions of its points, in
// the order of its indices (grid points first, then duplicates). All sums run one point at a
// time in that order, so they are bit for bit those of the per-point accumulation they replace:
// - box and centroid sum in float: Eigen's cwiseMin(box, v) is std::min(box, v) per
//   coordinate. The first point starts the box; a duplicate repeats an earlier point's
//   coordinates, so it would leave the box as it is and goes to the sum only. (Converting
//   here rather than keeping float copies from the fill: the moments read the same doubles
//   right after, while a copy was 16 more bytes a point to write and read, which cost on the
//   large clouds.) The centroid is the sum divided per coordinate, as Eigen's operator/=.
// - second moments about the float centroid cast to double. Only the six distinct entries
//   are summed: d d^T is symmetric (d_i d_j and d_j d_i are the same double), so the matrix
//   is filled from them once per primitive.
// A point's x, y, z (and a copy of z) go through the box and centroid in one float vector and
// through the moments in one double vector (GCC vector extensions): each lane the same
// conversion, min, max, difference, product and sum as the scalar code. This is the baseline
// code (SSE2, a point's four doubles in two halves); with AVX2 primitiveSumsAvx2 (below) runs.
// (Stored to `out` by memcpy: the vectors' layout is that of its arrays.)
using F4 = float __attribute__((vector_size(16)));
using D4 = double __attribute__((vector_size(32)));
using D2 = double __attribute__((vector_size(16)));
void plainSums(const std::uint32_t* __restrict sp, std::uint32_t ng, std::uint32_t np, const double* __restrict gx,
               const double* __restrict gy, const double* __restrict gz, PrimitiveSums& out)
{
  // (a macro: a lambda returning a 32-byte vector changes the ABI without AVX, -Wpsabi)
#define RC_XYZZ(p) (D4{gx[p], gy[p], gz[p], gz[p]})
  F4 lo = __builtin_convertvector(RC_XYZZ(sp[0]), F4), hi = lo, sum = F4{0, 0, 0, 0};
  for (std::uint32_t k = 0; k < ng; ++k)
  {
    const F4 v = __builtin_convertvector(RC_XYZZ(sp[k]), F4);
    lo = v < lo ? v : lo;  // std::min(lo, v), lane by lane
    hi = hi < v ? v : hi;  // std::max(hi, v)
    sum += v;
  }
  for (std::uint32_t k = ng; k < np; ++k) sum += __builtin_convertvector(RC_XYZZ(sp[k]), F4);  // duplicates
  const auto fn = static_cast<float>(np);
  const F4 centroid = sum / F4{fn, fn, fn, fn};
  const D4 c = __builtin_convertvector(centroid, D4);
  const D4 cz = D4{c[0], c[1], c[2], c[2]};
  D4 m = D4{0, 0, 0, 0};
  D2 mxy = D2{0, 0};
  for (std::uint32_t k = 0; k < np; ++k)
  {
    const D4 d = RC_XYZZ(sp[k]) - cz;  // (dx, dy, dz, dz)
    m += d * __builtin_shufflevector(d, d, 0, 1, 0, 3);  // (dx dx, dy dy, dz dx, dz dz)
    mxy += __builtin_shufflevector(d, d, 0, 1) * __builtin_shufflevector(d, d, 1, 2);  // (dx dy, dy dz)
  }
#undef RC_XYZZ
  std::memcpy(out.lo, &lo, sizeof lo);
  std::memcpy(out.hi, &hi, sizeof hi);
  std::memcpy(out.centroid, &centroid, sizeof centroid);
  std::memcpy(out.m, &m, sizeof m);
  std::memcpy(out.mxy, &mxy, sizeof mxy);
}

#if defined(RC_SIMD_CLONES_ON)
// plainSums with AVX2 intrinsics, the same operations lane by lane (so the same bits), in
// another data flow: a point's coordinates are three broadcast loads, and its vectors are made
// of them by blends. Gathered into a vector by inserts and shuffles (plainSums' data flow, which
// its AVX2 target clone had too), a point took three shuffles in the box pass and four in the
// moments pass, all on the one port that shuffles 256-bit vectors, which bound both loops; blends
// run on any of three ports, and a broadcast is a load alone.

// (x, y, z, z) of position p from three broadcasts
__attribute__((target("avx2"))) inline __m256d xyzzAvx2(const double* gx, const double* gy, const double* gz,
                                                       std::uint32_t p)
{
  const __m256d xy = _mm256_blend_pd(_mm256_broadcast_sd(gx + p), _mm256_broadcast_sd(gy + p), 0b0010);
  return _mm256_blend_pd(xy, _mm256_broadcast_sd(gz + p), 0b1100);
}
__attribute__((target("avx2"))) void primitiveSumsAvx2(const std::uint32_t* __restrict sp, std::uint32_t ng,
                                                       std::uint32_t np, const double* __restrict gx,
                                                       const double* __restrict gy, const double* __restrict gz,
                                                       PrimitiveSums& out)
{
  __m128 lo = _mm256_cvtpd_ps(xyzzAvx2(gx, gy, gz, sp[0])), hi = lo, sum = _mm_setzero_ps();
  for (std::uint32_t k = 0; k < ng; ++k)
  {
    const __m128 v = _mm256_cvtpd_ps(xyzzAvx2(gx, gy, gz, sp[k]));
    lo = _mm_min_ps(v, lo);  // v < lo ? v : lo, as std::min(lo, v)
    hi = _mm_max_ps(v, hi);  // v > hi ? v : hi, as std::max(hi, v)
    sum = _mm_add_ps(sum, v);
  }
  for (std::uint32_t k = ng; k < np; ++k)  // duplicates
    sum = _mm_add_ps(sum, _mm256_cvtpd_ps(xyzzAvx2(gx, gy, gz, sp[k])));
  const __m128 centroid = _mm_div_ps(sum, _mm_set1_ps(static_cast<float>(np)));
  const __m256d c = _mm256_permute4x64_pd(_mm256_cvtps_pd(centroid), 0xa4);  // (cx, cy, cz, cz)
  // The six products as d d (xx, yy, zz, zz) and d rot(d) (xy, yz, zx, -), rot(d) = (dy, dz, dx, dx):
  // each entry is still one product of the same two differences summed in the same order (zx as
  // dz dx, the same double as dx dz), in 8 vector operations a point where (dx, dy, dz, dz) times
  // (dx, dy, dx, dz) and (dx, dy) times (dy, dz), each pair built by blends and subtractions,
  // took 11: on this pass's three vector ports the operations, not the additions' latency, were
  // the bound. One lane-crossing permutation a point is all that port 5 gets.
  __m256d dd = _mm256_setzero_pd(), dr = _mm256_setzero_pd();
  for (std::uint32_t k = 0; k < np; ++k)
  {
    const __m256d d = _mm256_sub_pd(xyzzAvx2(gx, gy, gz, sp[k]), c);  // (dx, dy, dz, dz)
    dd = _mm256_add_pd(dd, _mm256_mul_pd(d, d));
    dr = _mm256_add_pd(dr, _mm256_mul_pd(d, _mm256_permute4x64_pd(d, 0x09)));
  }
  const __m256d m = _mm256_blend_pd(dd, dr, 0b0100);  // (xx, yy, zx, zz)
  const __m128d mxy = _mm256_castpd256_pd128(dr);     // (xy, yz)
  std::memcpy(out.lo, &lo, sizeof lo);
  std::memcpy(out.hi, &hi, sizeof hi);
  std::memcpy(out.centroid, &centroid, sizeof centroid);
  std::memcpy(out.m, &m, sizeof m);
  std::memcpy(out.mxy, &mxy, sizeof mxy);
}
#endif

}  // namespace

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
  plainSums(sp, ng, np, gx, gy, gz, out);
}

}  // namespace ring_curvature
