// The features' loops over one ring (see ring_kernels.hpp).
#include "features/ring_kernels.hpp"
#include "common/float_bits.hpp"

#include "common/angles.hpp"
#include "common/simd_clones.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ring_curvature
{
namespace detail
{
namespace
{
// One sample's chords from its own azimuth and range and its two chord ends' (p: incoming, n:
// outgoing); returns 1 when an angle exceeded the polynomial's range.
template <class SinCos>
inline int chordSample(float c, float az_k, float rho_k, float az_p, float rho_p, float az_n, float rho_n,
                       SinCos sinCos, float& cross, float& dot, float& v2, float& u2)
{
  constexpr float small = static_cast<float>(kSmallAngle);
  const float ap = c * wrapPi(az_p - az_k), an = c * wrapPi(az_n - az_k);
  const int large = (std::fabs(ap) > small ? 1 : 0) | (std::fabs(an) > small ? 1 : 0);
  float sp, cp, sn, cn;
  sinCos(ap, sp, cp);
  sinCos(an, sn, cn);
  const float vx = rho_k - rho_p * cp, vy = -(rho_p * sp);  // incoming chord
  const float ux = rho_n * cn - rho_k, uy = rho_n * sn;     // outgoing chord
  cross = vx * uy - vy * ux;
  dot = vx * ux + vy * uy;
  v2 = vx * vx + vy * vy;
  u2 = ux * ux + uy * uy;
  return large;
}
// chordProducts' loop (a side without neighbour degenerates harmlessly to the vertex). A function of
// its own for `__restrict`, which GCC honours on parameters, so that the gathers vectorize. Float
// keeps the turning angle to ~1e-6 rad: rho_k - rho_kp cos(a) loses ~1 ulp of the range against
// chords >= 0.25 m, and fastAtan2 is float anyway.
template <class SinCos>
inline bool chordKernel(int K, float c, const int* H, const int* L, const int* R, const float* __restrict az,
                        const float* __restrict rho, float* __restrict cross, float* __restrict dot,
                        float* __restrict v2, float* __restrict u2, SinCos sinCos)
{
  int large = 0;  // an int and `|`: no short-circuit branch in the loop
  for (int k = 0; k < K; ++k)
  {
    const int kp = k - std::min(H[k], L[k]), kn = k + std::min(H[k], R[k]);
    large |= chordSample(c, az[k], rho[k], az[kp], rho[kp], az[kn], rho[kn], sinCos, cross[k], dot[k], v2[k], u2[k]);
  }
  return large != 0;
}
}  // namespace

RC_SIMD_CLONES bool chordProducts(int K, float c, const int* H, const int* L, const int* R,
                                  const float* __restrict az, const float* __restrict rho, float* __restrict cross,
                                  float* __restrict dot, float* __restrict v2, float* __restrict u2, bool libm)
{
  if (libm) return chordKernel(K, c, H, L, R, az, rho, cross, dot, v2, u2, smallSinCos<float>);
  return chordKernel(K, c, H, L, R, az, rho, cross, dot, v2, u2, polySinCos<float>);
}

// Chord mode: samples per half chord for a chord of `chord` metres (spacing ~ rho cos(phi)
// dtheta), in [1, max_h]. The ceil by truncation is exact (quotient in (0, 2.5e5], below 2^24)
// and vectorizes, where SSE2 has no rounding instruction and std::ceil stays a call.
RC_SIMD_CLONES void chordSamples(int K, const float* __restrict rho, float cos_phi, float dtheta, float chord,
                                      int max_h, int* __restrict H)
{
  for (int k = 0; k < K; ++k)
  {
    const float spacing = rho[k] * cos_phi * dtheta;
    const float q = chord / (spacing > 1e-6f ? spacing : 1e-6f);  // NaN-safe
    const int t = static_cast<int>(q);
    H[k] = std::clamp(t + (static_cast<float>(t) < q ? 1 : 0), 1, max_h);
  }
}

// Jump mode: link (k-1, k) of each sample k on the padded ranges `rp`, the smaller relative
// misprediction of the two sides' linear extrapolations; NaN where L[k] = 0. Branch-free so it
// vectorizes. Float suffices: ~1 ulp (1e-7 of the range) is far below jump_min_ratio (0.03).
RC_SIMD_CLONES void linkJumps(int K, const int* __restrict L, const int* __restrict R, const float* __restrict rp,
                                   float* __restrict jump)
{
  constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();
  for (int k = 0; k < K; ++k)
  {
    const float r1 = rp[k], r0 = rp[k - 1], rm = rp[k - 2], r2 = rp[k + 1];
    const float e_flat = std::fabs(r1 - r0);
    const float e_left = L[k] >= 2 ? std::fabs(r1 - (2.0f * r0 - rm)) : e_flat;
    const float e_right = R[k] >= 1 ? std::fabs(r0 - (2.0f * r1 - r2)) : e_flat;
    const float j = std::min(e_left, e_right) / std::min(r0, r1);
    jump[k] = L[k] >= 1 ? j : kNaNf;
  }
}

// Discontinuity of each sample: the larger of its two links' jumps (jump[k] is link (k-1, k),
// NaN where there is none; jump[K] repeats jump[0] for the seam). NaN only when both are.
RC_SIMD_CLONES void largerLink(int K, const int* __restrict R, const float* __restrict jump,
                                    float* __restrict disc)
{
  constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();
  for (int k = 0; k < K; ++k)
  {
    const float d = jump[k];
    const float next = jump[k + 1];  // loaded unconditionally (jump has K + 1 entries): no branch
    const float dn = R[k] >= 1 ? next : kNaNf;
    const float larger = d < dn ? dn : d;  // std::max(d, dn), as values (it returns a reference)
    disc[k] = d != d ? dn : larger;        // d is NaN: the other link alone
  }
}

}  // namespace detail
}  // namespace ring_curvature
